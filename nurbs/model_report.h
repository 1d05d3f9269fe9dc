#pragma once
/// \file model_report.h
/// What a model read from a file lacks or changed against the file, and what that does to the
/// certificate of an answer on it. An answer is certified only for the model as the file
/// describes it:
/// - a face the reader dropped makes the model another model: no answer on it is certified unless
///   the caller accepts the partial model (ModelReport::uncertified_reason);
/// - a face whose trim loops could not be made valid (TrimmedSurface::trim_problem) may cover too
///   much or too little of its surface: no answer that may depend on it is certified (FaceDoubts);
/// - a face whose file edges lie off its surface (TrimmedSurface::edge_gap) has a boundary known
///   only that closely: every bound that may depend on it is widened by the gap (FaceDoubts).
#include <filesystem>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "nurbs/model.h"
#include "nurbs/model_ops.h"

namespace nurbs {

/// A face of the model (index into world_faces order) with what is doubtful about it.
struct FaceNote {
  int face = -1;     ///< index into world_faces(model)
  int face_id = -1;  ///< the file's id of the face (IGES directory entry, STEP instance number)
  std::string problem;
  double gap = 0.0;  ///< TrimmedSurface::edge_gap, model units
};

struct ModelReport {
  std::string source;
  int faces_in_file = -1;  ///< Model::faces_in_file (-1: the reader does not count them)
  int faces_read = 0;
  std::vector<DroppedFace> dropped;  ///< Model::dropped_faces
  std::vector<FaceNote> invalid_trims;
  std::vector<FaceNote> edge_gaps;
  std::vector<std::string> warnings;  ///< Model::read_warnings

  /// Faces of the file are missing from the model.
  [[nodiscard]] bool partial() const { return !dropped.empty(); }
  /// Anything at all differs from the letter of the file.
  [[nodiscard]] bool changed() const {
    return partial() || !invalid_trims.empty() || !edge_gaps.empty() || !warnings.empty();
  }
  /// The largest edge gap of any face (model units); 0 when none.
  [[nodiscard]] double largest_gap() const;
  /// Why an answer that may depend on every face (a ray cast, a thickness map) is not certified:
  /// the first face with an invalid trim; empty when there is none.
  [[nodiscard]] std::string invalid_trim_reason() const;
  /// Why no answer on the model is certified, empty when answers may be: faces were dropped and the
  /// caller does not accept the partial model.
  [[nodiscard]] std::string uncertified_reason(bool accept_partial) const;
  /// What differs, one line each for people ("3 of 580 faces dropped: ..."), at most `max_items`
  /// faces or warnings listed per kind.
  [[nodiscard]] std::vector<std::string> lines(size_t max_items = 5) const;
};

/// The report of `model` as read (faces indexed as world_faces(model) lists them).
[[nodiscard]] ModelReport model_report(const Model& model);

/// model_size(model), or RequestError "PATH: PROBLEM" when no tolerance can refer to it
/// (validate_model_size); `path` names the model in the message.
[[nodiscard]] double checked_model_size(const Model& model, const std::filesystem::path& path);

/// A model with its reader's report and the file it came from: what every query's front door takes
/// (nurbs::io::load_model reads one).
struct LoadedModel {
  Model model;
  ModelReport report;
  std::filesystem::path path;  ///< the file read; empty for a model built in memory (no disk cache)

  /// checked_model_size(model, path).
  [[nodiscard]] double checked_size() const { return checked_model_size(model, path); }
};

/// The doubtful faces of a face list, by box, for deciding per answer which of them it may depend
/// on: a face can hold the closest point to p only if its control-point box (which holds the
/// surface) lies within the answer's distance plus bound of p.
class FaceDoubts {
 public:
  /// `faces`: the faces a query runs on, in its order (world_faces or a subset).
  explicit FaceDoubts(const std::vector<TrimmedSurface>& faces);

  struct Verdict {
    double widen = 0.0;     ///< the largest edge gap of the faces within reach: add it to the bound
    int invalid_face = -1;  ///< a face with an invalid trim within reach (index), -1 when none
    std::string reason;     ///< why the answer is not certified, empty when it may be
  };
  /// For an answer of distance `d` with bound `b` at point `p`. A face's edge gap matters only where
  /// its file edges, within the gap of its trim boundary, may lie nearer to p than the answer: so
  /// the bound is widened only when a gapped face's boundary (its loops lifted to space) lies
  /// within d + b + 2 gap of p; an invalid trim matters wherever the face's box is within reach.
  [[nodiscard]] Verdict at(const glm::dvec3& p, double d, double b) const;
  /// For an answer that may depend on any face within `reach` of `box` (clearance: the other
  /// model's box, reach = distance + bound).
  [[nodiscard]] Verdict near(const Box& box, double reach) const;
  /// No face is doubtful.
  [[nodiscard]] bool empty() const { return doubts_.empty(); }

 private:
  /// A run of consecutive boundary samples of a gapped face, with its box.
  struct BoundaryRun {
    Box box;
    std::vector<glm::dvec3> points;
  };
  struct Doubt {
    Box box;
    int face;
    int face_id;
    double gap;
    std::string problem;
    std::vector<BoundaryRun> boundary;  ///< gapped faces: the loops lifted to space
    double slack = 0.0;                 ///< how far the sampled boundary may stray from the lifted loops
  };
  [[nodiscard]] static double boundary_distance(const Doubt& d, const glm::dvec3& p, double within);
  /// Marks v uncertified by the first face with an invalid trim for which within(box, v.widen) holds.
  template <class Within>
  void mark_invalid(Verdict& v, Within within) const;
  std::vector<Doubt> doubts_;
};

}  // namespace nurbs
