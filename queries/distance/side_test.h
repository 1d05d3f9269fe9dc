#pragma once
/// \file side_test.h
/// Which side of a model's closed solids a point lies on, for signed distances (negative inside):
/// first from the outward normal at the point's closest point, where that decides (the closest
/// point inside a face, away from its edges and trims, with p - closest within 25 degrees of the
/// normal line: there p - closest lies along the normal of the true closest point, up to the
/// answer's point bound); else by rays (Lemasson et al.'s caster, in double): from p along three
/// fixed directions, the first face each meets is left (inside) or entered (outside) by the ray,
/// or none is met (outside). The rays decide when at least two agree and none disagrees; grazing
/// hits abstain. Points the rays leave undecided are unsure.
#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <vector>

#include "nurbs/trimmed_surface.h"
#include "queries/distance/point_distance.h"

namespace queries {

class RayCaster;

enum class Side : signed char { Inside = -1, Unsure = 0, Outside = 1 };

struct SideFigures {
  size_t by_normal = 0, by_rays = 0, unsure = 0;
};

class SideTest {
 public:
  /// `faces`: the faces the answers index (world coordinates), oriented (TrimmedSurface::reversed
  /// says which side is out), bounding closed solids.
  explicit SideTest(const std::vector<nurbs::TrimmedSurface>& faces);
  ~SideTest();
  SideTest(const SideTest&) = delete;
  SideTest& operator=(const SideTest&) = delete;

  /// The side of every point with a found answer (Unsure where none); the rays' scene is built on
  /// the first call that needs it.
  [[nodiscard]] std::vector<Side> sides(std::span<const glm::dvec3> points, const std::vector<PointDistance>& answers);
  [[nodiscard]] const SideFigures& figures() const { return figures_; }

  /// The side by the normal at a's closest point alone (Unsure where that does not decide).
  [[nodiscard]] Side by_normal(const glm::dvec3& p, const PointDistance& a) const;

 private:
  const std::vector<nurbs::TrimmedSurface>& faces_;
  std::unique_ptr<RayCaster> caster_;
  SideFigures figures_;
};

}  // namespace queries
