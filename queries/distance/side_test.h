#pragma once
/// \file side_test.h
/// Which side of a model's closed solids a point lies on, for signed distances (negative inside).
/// The model is the union of its solids: a point inside any of them is inside, one outside all of
/// them is outside, and the distance is to the union's boundary.
///
/// A point's side within one solid: first from the outward normal at the point's closest point,
/// where that decides (the closest point inside a face, away from its edges and trims, with
/// p - closest within 25 degrees of the normal line: there p - closest lies along the normal of the
/// true closest point, up to the answer's point bound); else by rays (Lemasson et al.'s caster, in
/// double) cast at that solid's faces alone: from p along three fixed directions, the first face
/// each meets is left (inside) or entered (outside) by the ray, or none is met (outside). The rays
/// decide when at least two agree and none disagrees; grazing hits abstain. Rays cast at every
/// solid at once would not do: from a point inside one solid the first face met may be another's,
/// entered where the two overlap.
///
/// The union's side: inside as soon as one solid holds the point (by its normal or its rays);
/// outside when the normal puts it outside its closest face's solid and the rays outside every
/// other solid whose box holds it (a point outside a solid's box is outside the solid); unsure
/// otherwise.
///
/// The union's distance: outside the union the nearest face point is on the union's boundary
/// (a segment from the point to a face point inside another solid would cross that solid's
/// boundary first). From a point inside, the nearest face point may lie inside another solid, or
/// on a face it shares with another (two solids seated on one another): the union's boundary is
/// then farther. Such an answer is `hidden`: its closest point lies in another solid's box and six
/// rays from it (three directions both ways) cast at that solid's faces do not show it outside
/// that solid by more than the answer's bound (a hit nearer, an inside vote, or no decision).
#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <vector>

#include "nurbs/model_ops.h"
#include "nurbs/trimmed_surface.h"
#include "queries/distance/point_distance.h"

namespace queries {

class RayCaster;

enum class Side : signed char { Inside = -1, Unsure = 0, Outside = 1 };

struct SideFigures {
  size_t by_normal = 0, by_rays = 0, unsure = 0;
  /// Answers inside (or unsure) whose closest point may lie inside or on another solid.
  size_t hidden = 0;
};

struct SideAnswer {
  Side side = Side::Unsure;
  /// For an answer inside or unsure: the solid that may hold its closest point (the union's
  /// boundary is then farther than the answer), else -1.
  int hidden_by = -1;
};

class SideTest {
 public:
  /// `faces`: the faces the answers index (world coordinates), oriented (TrimmedSurface::reversed
  /// says which side is out), bounding closed solids; `solid_of_face`: per face the solid it
  /// bounds (empty: one solid).
  explicit SideTest(const std::vector<nurbs::TrimmedSurface>& faces, std::vector<int> solid_of_face = {});
  ~SideTest();
  SideTest(const SideTest&) = delete;
  SideTest& operator=(const SideTest&) = delete;

  /// The side of every point with a found answer (Unsure where none), and whether its closest
  /// point may be hidden by another solid; the rays' scenes are built per solid on the first call
  /// that needs them. `normals`: per answer, the outward normal at its closest point
  /// (PointQueryResult::normals, nurbs::outward_normal).
  [[nodiscard]] std::vector<SideAnswer> sides(std::span<const glm::dvec3> points,
                                              const std::vector<PointDistance>& answers,
                                              std::span<const glm::dvec3> normals);
  [[nodiscard]] const SideFigures& figures() const { return figures_; }

  /// The side by the outward normal `n` at a's closest point alone, within that face's solid
  /// (Unsure where that does not decide).
  [[nodiscard]] Side by_normal(const glm::dvec3& p, const PointDistance& a, const glm::dvec3& n) const;

 private:
  struct Solid;
  /// One ray query at a solid: from `origin`, asked for point `k`.
  struct Ask {
    size_t k;
    int solid;
    glm::dvec3 origin;
  };
  /// Per ask, the solid's side of its origin by three rays (`both_ways`: six, and a hit nearer
  /// than `near[k]` makes it Unsure).
  std::vector<Side> ask(const std::vector<Ask>& asks, bool both_ways, const std::vector<double>& near);
  /// The solids (other than `except`) whose box holds p.
  void solids_at(const glm::dvec3& p, int except, std::vector<int>& out) const;

  const std::vector<nurbs::TrimmedSurface>& faces_;
  std::vector<int> solid_of_face_;
  std::vector<Solid> solids_;
  SideFigures figures_;
};

}  // namespace queries
