#pragma once
/// \file clearance_pair.h
/// The front door of the clearance query (Krishnamurthy et al. §5): two models prepared once and
/// queried at any number of placements of B, everything a caller needs decided in one place:
///  - one body of each model when asked (an assembly's part), B scaled into A's unit;
///  - before any grid, the faces that cannot hold the closest pair at the placements asked for
///    left out (face_cull.h; beyond the paper), the answers naming faces by their index in the model;
///  - each model at half the tolerance (clearance_model_tolerance), less the reader's edge gaps;
///  - the search on the CPU alone (clearance_cpu) for one placement of small models, before any GL
///    context, the GPU taking over past its budget; the GPU descent otherwise (clearance.h), A's
///    hierarchy kept between placements; the §5.4 voxel stage first when asked;
///  - every answer judged against the reader's doubts of either model (nurbs/model_report.h): its
///    bound widened by edge gaps within reach, uncertified near an invalid trim or on a model that
///    lost faces.
#include <functional>
#include <glm/mat4x4.hpp>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/model_report.h"
#include "nurbs/paper_switch.h"
#include "queries/distance/clearance.h"
#include "queries/distance/point_query.h"
#include "queries/distance/prepared_model.h"
#include "queries/distance/voxel_stage.h"

namespace queries {

struct ClearanceOptions {
  double tolerance = 1e-5;  ///< every answer's bound, relative to the larger model size
  Search search = Search::CoarseToFine;
  bool voxel_stage = false;  ///< §5.4: the voxel grid first, then the hierarchy over the faces it keeps
  int voxels = 40;           ///< voxels per axis of the voxel stage
  ClearanceLimits limits;    ///< the GPU descent's settings
  long long max_samples = kDefaultMaxSamples;  ///< per face grid
  /// Leave out, before any grid, the faces whose control boxes lie farther from every face of the
  /// other model than an upper bound from material samples (at the placements prepare() is given).
  bool face_cull = true;
  /// Auto: the CPU alone for one placement whose kept faces' coarse grids hold at most
  /// kCpuClearanceStartPairs cell pairs, the GPU otherwise; Cpu needs coarse-to-fine without the
  /// voxel stage.
  EngineChoice engine = EngineChoice::Auto;
  bool accept_partial = false;  ///< answers on a model whose reader dropped faces may be certified
  /// The GPU profiler reset, enabled and synchronised once the GPU is ready: its table then holds
  /// the queries' passes alone.
  bool profile_queries = false;
  /// One body of each model (its index or name as the model lists them); empty: every body.
  std::string body_a, body_b;

  /// These options with every setting Krishnamurthy et al. fix at the paper's value: faithful grids
  /// (§5.1), every face prepared and the voxel stage first (§5.4) at the 40^3 grid of the paper's
  /// tests (§6), the descent on the GPU (§5.1) with log2 reductions of 2 x 2 texels and a 4-texel
  /// count pyramid (§1.1), every level on the GPU (§5.1), U from the boxes' farthest points (§5.2),
  /// the descent from the roots (§5.1).
  [[nodiscard]] ClearanceOptions paper() const;
  [[nodiscard]] static std::vector<nurbs::PaperSwitch> paper_switches();
};

/// The figures of the face cull (ClearanceOptions::face_cull).
struct FaceCullFigures {
  bool on = false;
  size_t faces_a = 0, faces_b = 0;  ///< kept
  size_t face_pairs = 0;
  double upper = 0.0;
  double seconds = 0.0;
};

/// One answer of ClearancePair::query.
struct ClearanceAnswer {
  /// The clearance; faces indexed as nurbs::world_faces of each (selected) model lists them; bound
  /// widened by the reader's edge gaps within reach; meets_tolerance false when `reason` is set.
  Clearance clearance;
  std::string reason;  ///< why it is not certified; empty when it may be
  double widen = 0.0;  ///< of the bound, by what the reader's edge gaps can change
  /// Where widen > 0: the model ("A" or "B"), face (index into that model's faces) and gap that set it.
  std::string gap_model;
  int gap_face = -1, gap_face_id = -1;
  double gap = 0.0;
  bool on_cpu = false;  ///< answered by clearance_cpu
  std::optional<VoxelStage> first_stage;  ///< the voxel stage of this placement
  double first_stage_seconds = 0.0;
  double seconds = 0.0;
  double tolerance = 0.0;  ///< T, model units (A's)

  /// Found, certified and its bound within T.
  [[nodiscard]] bool meets() const;
  /// Certified, over T only by the widening of the reader's edge gaps: certified to the file's precision.
  [[nodiscard]] bool limited_by_file() const;
  /// Why the answer is limited by the file, for people; empty when it is not.
  [[nodiscard]] std::string file_precision() const;
  /// Why it is not certified, for people; empty when it is (meets T, or, unless `strict`, over it only
  /// by the file's precision).
  [[nodiscard]] std::string failure(bool strict = false) const;
  /// Why it falls short of T, whatever the reason (file_precision when limited by the file, else
  /// failure(true)); empty when it meets T: the answer's `reason` in JSON and Python.
  [[nodiscard]] std::string shortfall() const;
};

class ClearancePair {
 public:
  /// Selects the bodies and scales B into A's unit. `b` null: B is A's file (another body of it, or
  /// the same). `gpu`: a GL context to run on; null: one started by `start` when a query needs it.
  /// Throws nurbs::RequestError for a body the model does not have or a model without a size.
  ClearancePair(const nurbs::LoadedModel& a, const nurbs::LoadedModel* b, ClearanceOptions options,
                gpgpu::Gpu* gpu, GpuStart start = {});
  ~ClearancePair();
  ClearancePair(const ClearancePair&) = delete;
  ClearancePair& operator=(const ClearancePair&) = delete;

  /// The largest coordinate of B's move that double arithmetic carries for both models (A's unit).
  [[nodiscard]] double move_limit() const { return move_limit_; }
  /// Prepares both models for the placements `frames` of B (rigid motions; the face cull keeps the
  /// faces for those). Empty: any placement (every face kept, the GPU descent), as an interactive
  /// caller needs. Throws nurbs::RequestError for a face whose grid cannot meet the tolerance.
  void prepare(std::span<const glm::dmat4> frames);
  /// The clearance at B's placement `motion`: one of prepare()'s frames when the faces were culled.
  [[nodiscard]] ClearanceAnswer query(const glm::dmat4& motion);

  [[nodiscard]] const ClearanceOptions& options() const { return options_; }
  [[nodiscard]] double tolerance() const { return tolerance_; }            ///< T, A's unit
  [[nodiscard]] double grid_tolerance() const { return grid_tolerance_; }  ///< each model's
  [[nodiscard]] const nurbs::Model& model_a() const { return a_; }
  [[nodiscard]] const nurbs::Model& model_b() const { return b_ ? *b_ : a_; }
  [[nodiscard]] size_t faces_a() const { return faces_a_; }  ///< faces of the selected body (before the cull)
  [[nodiscard]] size_t faces_b() const { return faces_b_; }
  [[nodiscard]] const PreparedModel& prepared_a() const { return pair_.a; }
  [[nodiscard]] const PreparedModel& prepared_b() const { return pair_.b; }
  [[nodiscard]] const FaceCullFigures& face_cull() const { return cull_; }
  [[nodiscard]] double prepare_seconds() const { return prepare_seconds_; }
  [[nodiscard]] long long cpu_queries() const { return cpu_queries_; }
  [[nodiscard]] long long gpu_queries() const { return gpu_queries_; }
  /// "cpu", "gpu" or "cpu and gpu": where the queries so far ran ("gpu" before any).
  [[nodiscard]] std::string engine_used() const;
  /// The GL context the queries ran on; null while none was needed.
  [[nodiscard]] gpgpu::Gpu* gpu() const { return gpu_; }

 private:
  void start_gpu();
  void ensure_gpu();
  Clearance query_kept(const glm::dmat4& motion, ClearanceAnswer& out);

  ClearanceOptions options_;
  nurbs::Model a_;
  std::optional<nurbs::Model> b_;  ///< B when it is not A itself
  std::string model_reason_;
  double size_ = 0.0, tolerance_ = 0.0, grid_tolerance_ = 0.0, move_limit_ = 0.0;
  std::vector<nurbs::TrimmedSurface> fa_, fb_;  ///< the faces (B in A's unit) until prepare()
  size_t faces_a_ = 0, faces_b_ = 0;
  std::vector<int> index_a_, index_b_;  ///< kept face -> face of the model
  std::optional<nurbs::FaceDoubts> doubts_a_, doubts_b_;
  nurbs::Box box_a_{}, box_b_{};
  std::vector<nurbs::Box> boxes_a_, boxes_b_;  ///< each face's control box, in its model's frame
  std::vector<glm::dmat4> frames_;  ///< prepare()'s, when the faces were culled for them
  std::unique_ptr<gpgpu::Gpu> own_gpu_;  ///< declared before what holds GL objects: destroyed last
  PreparedPair pair_;
  bool prepared_ = false, try_cpu_ = false, gpu_ready_ = false, atlases_ = false, trimmed_ = false;
  gpgpu::Gpu* gpu_ = nullptr;
  GpuStart start_;
  VoxelGrid voxels_a_, voxels_b_;
  FaceCullFigures cull_;
  std::unique_ptr<ClearanceCache> cache_;  ///< A's hierarchy; destroyed before the GPU
  double prepare_seconds_ = 0.0;
  long long cpu_queries_ = 0, gpu_queries_ = 0;
};

}  // namespace queries
