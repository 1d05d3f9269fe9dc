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
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nurbs/median_tree.h"
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
///
/// What an edge gap g of a face means (docs/distance.md, "The file's precision"): the file's face F'
/// and ours F (the surface inside the trim loops B lifted to space) differ only within g of B, and
/// there lie within g of each other: (i) F' lies in F and the g-neighbourhood of B; (ii) the points
/// of F farther than g from B belong to F'; (iii) every point of F has a point of F' within g.
class FaceDoubts {
 public:
  /// `faces`: the faces a query runs on, in its order (world_faces or a subset).
  explicit FaceDoubts(const std::vector<TrimmedSurface>& faces);

  /// A point of our faces that certifies an answer's upper end: some point y of the faces lies within
  /// `within` of `point`, and no farther than d + b from p. The true closest point qualifies with
  /// the answer's point and Theorem 2's sqrt(4 K d + K^2) (PointDistance::point_bound); so does the
  /// nearest face point of a mesh point at distance d, with the mesh's eps.
  struct Witness {
    glm::dvec3 point{0.0};
    double within = 0.0;
  };
  struct Verdict {
    double widen = 0.0;     ///< what the edge gaps within reach can change: add it to the bound
    int gap_face = -1;      ///< the gapped face that sets `widen` (index), -1 when none
    int gap_face_id = -1;   ///< the file's id of that face
    double gap = 0.0;       ///< its edge gap, model units
    int invalid_face = -1;  ///< a face with an invalid trim within reach (index), -1 when none
    std::string reason;     ///< why the answer is not certified, empty when it may be
  };
  /// For an answer of distance `d` with bound `b` (|d - d*| < b, d* the distance to our faces) at
  /// point `p`, the widening that makes |d - d'| < b + widen for the distance d' to the file's faces:
  /// - below, by (i): d' >= min(d*, dist(p, B) - g), so only a gapped boundary nearer than
  ///   d - b + g widens, by d - b + g - dist(p, B) (at most g, never below 0);
  /// - above, by (ii) and (iii): d' <= d + b when the witness y lies farther than g from every
  ///   gapped boundary (y then belongs to F'), and d' <= d* + g always; without a witness, every
  ///   point of F within d + b of p must lie that far.
  /// An invalid trim matters wherever the face's box is within reach of the widened answer.
  [[nodiscard]] Verdict at(const glm::dvec3& p, double d, double b,
                           const std::optional<Witness>& closest = std::nullopt) const;
  /// For an answer that may depend on any face within `reach` of `box`: invalid trims only (the
  /// thickness and ray queries' faces).
  [[nodiscard]] Verdict near(const Box& box, double reach) const;

  /// One side of a clearance d with bound b between these faces and another model's (their boxes
  /// `others`, in this side's frame): what this side's gaps can change (docs/distance.md).
  struct Side {
    double gap = 0.0;  ///< the largest gap of a face whose boundary may come within the lower end's reach
    /// A lower bound of the distance from those faces' boundaries to `others`; +inf when none.
    double boundary = std::numeric_limits<double>::infinity();
    double cut = 0.0;  ///< the largest gap whose boundary lies within it (and the witness's `within`) of the witness
    Verdict verdict;   ///< the face that sets the larger of gap and cut, and any invalid trim within reach
  };
  /// `reach`: how far below the answer's lower end a boundary matters (the lower end plus both
  /// models' largest gaps); `witness`: a point of these faces within `within` of its point and
  /// within d + b of the other model's faces (without one, every face within d + b + gap of
  /// `others` counts as cut).
  [[nodiscard]] Side side(const std::vector<Box>& others, double low, double reach, double d, double b,
                          const std::optional<Witness>& witness) const;
  /// The widening of a clearance d +- b by both sides' gaps: below, the boundaries of either side
  /// within the two gaps of the lower end; above, the sum of the gaps at the witnesses.
  [[nodiscard]] static Verdict clearance(const Side& a, const Side& b, double d, double bound);
  /// The largest gap of any face; 0 when none.
  [[nodiscard]] double largest_gap() const;
  /// No face is doubtful.
  [[nodiscard]] bool empty() const { return doubts_.empty(); }

 private:
  /// A run of consecutive boundary samples of a gapped face, with its box and how far the lifted
  /// loop between its samples strays from their chords (twice the farthest parameter midpoint).
  struct BoundaryRun {
    Box box;
    std::vector<glm::dvec3> points;
    double slack = 0.0;
  };
  struct Doubt {
    Box box;
    int face;
    int face_id;
    double gap;
    std::string problem;
    std::vector<BoundaryRun> boundary;  ///< gapped faces: the loops lifted to space
  };
  /// A lower bound of the distance from p to the face's lifted loops, exact up to the runs' slack;
  /// +inf when that is beyond `within`.
  [[nodiscard]] static double boundary_distance(const Doubt& d, const glm::dvec3& p, double within);
  /// A lower bound of the distance from the face's lifted loops to any of `boxes`; +inf beyond `within`.
  [[nodiscard]] static double boundary_distance(const Doubt& d, const std::vector<Box>& boxes, double within);
  /// Marks v uncertified by the first face with an invalid trim for which within(box, v.widen) holds.
  template <class Within>
  void mark_invalid(Verdict& v, Within within) const;
  /// Per gapped face whose lifted loops come within `radius` of q: (index into doubts_, the
  /// boundary_distance lower bound), ascending by index; from the tree of every face's runs.
  void boundaries_near(const glm::dvec3& q, double radius, std::vector<std::pair<int, double>>& out) const;
  std::vector<Doubt> doubts_;
  /// Every gapped face's boundary runs (doubt index, run index) in one median tree.
  std::vector<std::pair<int, int>> runs_;
  std::shared_ptr<const MedianTree> run_tree_;
  double largest_slack_ = 0.0, largest_gap_ = 0.0;
  std::vector<int> invalid_;  ///< the doubts with an invalid trim, in order
};

}  // namespace nurbs
