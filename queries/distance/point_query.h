#pragma once
/// \file point_query.h
/// The front door of the point-set query: minimum distance from many points to a model with the
/// bounds of Krishnamurthy et al. §4, everything a caller needs decided in one place. PointQuery
/// prepares the model once (refusing, before the work, a preparation beyond the memory free or a
/// face whose grid cannot meet the tolerance), from the disk cache when an earlier run stored it,
/// picks the engine, and answers batches of points; every answer comes sanitised (a distance only
/// with a face and finite figures), its bound widened by the reader's edge gaps near it, and with
/// the reason when it is not certified.
///
/// Three paths:
///  - mesh (the default, beyond the paper): a guaranteed tessellation within the tolerance on the
///    knot-aligned grids, its triangles in Embree's BVH (mesh_distance.h): every answer's bound is
///    the mesh's proven distance to the faces; taken unless an engine of the pyramid is asked for, and left
///    for the batched path when the mesh would exceed its cell limit or a face cannot be meshed;
///  - batched: all points descend one box pyramid per atlas (point_batch.h), on
///    faithful grids within 1 GB and the memory free, else coarse ones, every answer over the
///    tolerance refined in double;
///  - per point (`per_point`, the paper's §3.1): one query at a time (point_distance.h), with the
///    search and host-cell settings.
#include <filesystem>
#include <functional>
#include <future>
#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/model_report.h"
#include "nurbs/paper_switch.h"
#include "queries/engine.h"
#include "queries/distance/mesh_distance.h"
#include "queries/distance/point_batch.h"
#include "queries/distance/side_test.h"
#include "queries/distance/point_distance.h"
#include "queries/distance/prepared_model.h"

namespace queries {

/// The rule every answer is held to: a bound within the tolerance T (both in model units), with
/// room for the rounding of T itself.
[[nodiscard]] inline bool within_tolerance(double bound, double tolerance) {
  return bound <= tolerance * (1.0 + 1e-12);
}
/// An answer meets T: found, its own search met it, and its bound is within T.
[[nodiscard]] inline bool meets_tolerance(const PointDistance& d, double tolerance) {
  return d.found && d.meets_tolerance && within_tolerance(d.bound, tolerance);
}

/// How a query of many points is answered (PointQueryOptions::path).
enum class PointPath {
  Auto,     ///< Mesh, unless an engine (gpu or cpu) is asked for or the mesh cannot be made
  Mesh,     ///< the certified mesh (mesh_distance.h); the batched path when it cannot be made
  Batched,  ///< the box pyramid of the grids (point_batch.h)
};
[[nodiscard]] const char* path_name(PointPath path);  ///< "auto", "mesh" or "batched"
/// "auto", "mesh" or "batched"; std::invalid_argument for another name.
[[nodiscard]] PointPath point_path(const std::string& name);

struct PointQueryOptions {
  double tolerance = 1e-5;  ///< every answer's bound, relative to the model size
  /// Many points: the certified mesh or the grids' box pyramid (per_point overrides both).
  PointPath path = PointPath::Auto;
  /// One query at a time (PointDistanceQuery) instead of the batched projection; `search` and
  /// `host_cells` apply to it alone.
  bool per_point = false;
  Search search = Search::CoarseToFine;
  long long host_cells = -1;  ///< PointDistanceQuery::set_host_cells
  /// Batched: the box pyramid the points descend.
  PointBoxes boxes = PointBoxes::Oriented;
  long long max_samples = kDefaultMaxSamples;  ///< per face grid
  /// Batched with oriented boxes: the atlases and pyramid read from and stored in the disk cache
  /// (batch_cache.h) when the model came from a file. Not while the GPU dumps textures (the dump
  /// wants the passes that make them).
  bool cache = true;
  EngineChoice engine = EngineChoice::Auto;  ///< batched: where the points descend the pyramid
  /// Answers on a model whose reader dropped faces may be certified, on the faces read.
  bool accept_partial = false;
  /// Also the signed distance of every point, negative inside the model's solids (side_test.h);
  /// refused for a model with a body the file does not state closed, or whose faces do not close.
  bool signed_distance = false;
  /// Called as a batch is answered: points done, points in all.
  std::function<void(size_t done, size_t total)> progress;
  /// Lines for people about the work (a slow preparation, a cache file not used or not written).
  std::function<void(const std::string&)> log;

  /// These options with every setting Krishnamurthy et al. fix at the paper's value: one point at
  /// a time (§3.1: the batched projection is beyond it), every face on its grid at the tolerance
  /// (§3.1, §4), every atlas pruned by the GPU's reduction and stream reduction (§3.1).
  [[nodiscard]] PointQueryOptions paper() const;
  /// The settings paper() changes, with their sections.
  [[nodiscard]] static std::vector<nurbs::PaperSwitch> paper_switches();
};

/// The disk cache of a batched preparation, as used.
struct PointQueryCache {
  bool used = false;  ///< looked up (and stored on a miss)
  bool hit = false;   ///< the preparation came from it
  std::filesystem::path file;
  std::string problem;        ///< why an existing file was not used (then rebuilt and written over)
  std::string write_problem;  ///< why the preparation could not be stored
  double read_seconds = -1.0, write_seconds = -1.0;  ///< -1: not read / not written
};

/// Where the file's precision sets an answer's bound (nurbs::FaceDoubts::at).
struct FileLimit {
  double widen = 0.0;    ///< what the edge gaps within reach added to the bound, model units
  int face = -1;         ///< the gapped face that set it (index into the query's faces), -1 when none
  int face_id = -1;      ///< the file's id of that face
  double gap = 0.0;      ///< its edge gap
  bool limited = false;  ///< the answer is over T only by `widen`: certified to the file's precision
};

struct PointQueryResult {
  /// One per point, in input order: found only with a face and finite figures; bound widened by
  /// what the reader's edge gaps near the answer can change; meets_tolerance false where
  /// `reasons` says why.
  std::vector<PointDistance> answers;
  /// Per answer, why it is not certified (a dropped face, an invalid trim within reach); empty
  /// where it may be.
  std::vector<std::string> reasons;
  /// Per answer, why a found, certified answer's bound is over T (the file's precision, the search's
  /// budget, the float slack), or why it was not found; empty where it meets T.
  std::vector<std::string> over_reasons;
  std::vector<FileLimit> file_limits;  ///< per answer
  /// Per answer, the face's outward unit normal at the closest point's (u, v) (zero where not found).
  std::vector<glm::dvec3> normals;
  double tolerance = 0.0;  ///< T, model units
  size_t not_found = 0;
  size_t over_tolerance = 0;   ///< found, certified, bound over T (limited_by_file among them)
  size_t uncertified = 0;
  size_t limited_by_file = 0;  ///< over T only by the reader's edge gaps near them
  double seconds = 0.0;  ///< answering the points
  /// PointQueryOptions::signed_distance: per answer the distance, negative inside (NaN where not
  /// found); its bound is the answer's, widened by 2 d where no side was found (either side is then
  /// possible): such an answer is certified only if that still meets the tolerance.
  std::vector<double> signed_distance;
  SideFigures sides;  ///< how the sides were found
  /// Why no answer on the model is certified (faces dropped, not accepted); empty when none.
  std::string model_reason;

  /// Answer k is certified and within T.
  [[nodiscard]] bool meets(size_t k) const { return reasons[k].empty() && meets_tolerance(answers[k], tolerance); }
  /// Answer k is certified, within T or over it only by the file's precision.
  [[nodiscard]] bool certified(size_t k) const { return meets(k) || file_limits[k].limited; }
  /// Why the answer k falls short (not certified, not found, over T), empty when it meets T.
  [[nodiscard]] const std::string& reason(size_t k) const { return reasons[k].empty() ? over_reasons[k] : reasons[k]; }
  /// Every answer meets T.
  [[nodiscard]] bool all_meet() const { return failure(true).empty(); }
  /// Why the query fails, for people (the command's exit-1 message), every class counted; empty
  /// when every answer is certified. An answer over T only by the file's precision fails it only
  /// when `strict`.
  [[nodiscard]] std::string failure(bool strict = false) const;
  /// The answers certified to the file's precision, for people: how many, and every gapped face
  /// that limits them with its gap; empty when none.
  [[nodiscard]] std::string file_precision() const;
};

class PointQuery {
 public:
  /// Prepares `model` for point queries at `options.tolerance`. Throws nurbs::RequestError for a
  /// model without a size, a face whose grid cannot meet the tolerance within max_samples, or a
  /// preparation larger than the memory free.
  PointQuery(gpgpu::Gpu& gpu, const nurbs::LoadedModel& model, PointQueryOptions options);
  ~PointQuery();
  PointQuery(const PointQuery&) = delete;
  PointQuery& operator=(const PointQuery&) = delete;

  /// The answers for `points` (model units, the model's frame).
  [[nodiscard]] PointQueryResult query(std::span<const glm::dvec3> points);

  [[nodiscard]] const PointQueryOptions& options() const { return options_; }
  [[nodiscard]] bool batched() const { return batch_.has_value(); }
  /// The certified mesh answers the points (PointPath::Mesh, or Auto resolved to it).
  [[nodiscard]] bool meshed() const { return mesh_ != nullptr; }
  /// The certified mesh, when meshed().
  [[nodiscard]] const MeshDistance* mesh() const { return mesh_.get(); }
  /// Why the mesh path was asked for (or Auto) and not taken; empty when it was, or not considered.
  [[nodiscard]] const std::string& mesh_refused() const { return mesh_refused_; }
  [[nodiscard]] double model_size() const { return size_; }
  [[nodiscard]] double tolerance() const { return options_.tolerance * size_; }
  /// The faces queried (nurbs::world_faces of the model): answers' `face` index them.
  [[nodiscard]] const std::vector<nurbs::TrimmedSurface>& faces() const { return faces_; }
  [[nodiscard]] double prepare_seconds() const { return prepare_seconds_; }
  [[nodiscard]] BatchEngine engine() const { return engine_; }
  /// Batched: the grids' search (Faithful within the memory, CoarseToFine else).
  [[nodiscard]] Search grids() const;
  [[nodiscard]] long long samples() const;  ///< grid samples over every face
  /// Per point: the host-cell limit in force; 0 batched.
  [[nodiscard]] long long host_cells_used() const { return single_ ? single_->host_cells_used() : 0; }
  /// Batched: the figures of the last query (PointBatch::stats).
  [[nodiscard]] const PointBatchStats& stats() const;
  /// The disk cache as used; complete once query() returned (the store runs beside the first batch).
  [[nodiscard]] const PointQueryCache& cache() const { return cache_; }
  /// Batched: the pyramid and atlases, for queries of their own (the rolling ball).
  [[nodiscard]] PointBatch& batch() { return *batch_; }

 private:
  void prepare_batched(gpgpu::Gpu& gpu, const std::filesystem::path& path, double query_tolerance);
  /// The certified mesh at `query_tolerance`; false (mesh_refused_ says why) when it cannot be made.
  bool prepare_mesh(double query_tolerance);
  void finish_cache_write();
  /// RequestError unless every body is stated closed and its faces close (a coarse watertight mesh
  /// has no open edges on them).
  static void require_closed_solids(const nurbs::LoadedModel& model);
  /// The signed distances and sides of `out`'s answers (signed_distance).
  void sign_answers(std::span<const glm::dvec3> points, PointQueryResult& out);

  PointQueryOptions options_;
  std::string model_reason_;  ///< ModelReport::uncertified_reason
  double size_ = 0.0;
  double query_tolerance_ = 0.0;  ///< T less the reader's largest edge gap, at least T / 2
  std::vector<nurbs::TrimmedSurface> faces_;
  nurbs::FaceDoubts doubts_;
  BatchEngine engine_ = BatchEngine::Gpu;
  std::optional<PointDistanceQuery> single_;
  std::optional<PreparedModel> prepared_;
  std::optional<PointBatch> batch_;
  std::unique_ptr<MeshDistance> mesh_;
  std::string mesh_refused_;
  PointQueryCache cache_;
  std::future<std::pair<std::string, double>> cache_write_;
  double prepare_seconds_ = 0.0;
  bool told_prepared_ = false;  ///< the preparation's time logged (once, with the first query)
  std::unique_ptr<SideTest> sides_;  ///< signed_distance
};

}  // namespace queries
