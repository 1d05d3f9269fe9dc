#include "nurbs/raycast/ball_thickness.h"

#include <glm/geometric.hpp>
#include <stdexcept>

namespace nurbs::ray {

std::vector<BallThickness> ball_thickness(const std::vector<glm::dvec3>& points, const std::vector<glm::dvec3>& inward,
                                          const std::vector<double>& start_radius, const NearestFn& nearest,
                                          const BallOptions& options, BallFigures* figures) {
  if (inward.size() != points.size() || start_radius.size() != points.size())
    throw std::invalid_argument("ball_thickness: as many normals and start radii as points needed");
  if (!(options.tolerance > 0.0)) throw std::invalid_argument("ball_thickness: the tolerance must be > 0");
  std::vector<BallThickness> out(points.size());
  std::vector<double> radius(points.size(), 0.0);
  std::vector<double> shrink_error(points.size(), 0.0);  ///< first-order error of r from the last shrinking q
  std::vector<size_t> active;
  for (size_t i = 0; i < points.size(); ++i) {
    radius[i] = start_radius[i] > 0.0 ? start_radius[i] : options.max_radius;
    if (radius[i] > 0.0) active.push_back(i);
  }
  BallFigures f;
  std::vector<glm::dvec3> centres;
  std::vector<double> within;
  for (int round = 0; round < options.max_rounds && !active.empty(); ++round) {
    centres.clear();
    within.clear();
    for (size_t i : active) {
      centres.push_back(points[i] + radius[i] * inward[i]);
      within.push_back(radius[i] - options.tolerance);
    }
    const std::vector<NearestPoint> q = nearest(centres, within);
    if (q.size() != centres.size()) throw std::logic_error("ball_thickness: the query answered another count");
    ++f.rounds;
    f.queries += static_cast<long long>(centres.size());
    std::vector<size_t> next;
    for (size_t k = 0; k < active.size(); ++k) {
      const size_t i = active[k];
      BallThickness& b = out[i];
      ++b.rounds;
      const double r = radius[i];
      b.bound = 2.0 * (2.0 * q[k].bound + options.tolerance + shrink_error[i]);
      if (!q[k].found) {  // nothing nearer than r - tolerance - the query's bound: empty
        b.converged = true;
        continue;
      }
      b.contact = q[k].point;
      b.contact_face = q[k].face;
      if (q[k].distance >= r - (q[k].bound + options.tolerance)) {
        b.converged = true;
        continue;
      }
      const glm::dvec3 e = q[k].point - points[i];
      const double along = glm::dot(inward[i], e);
      const double r_new = along > 0.0 ? glm::dot(e, e) / (2.0 * along) : -1.0;
      if (!(r_new > 0.0) || !(r_new < r)) continue;  // degenerate (q at p within round-off): keep r
      radius[i] = r_new;
      // dr / dq = (q - c_new) / (n . (q - p)), |q - c_new| = r_new: a surface point within the
      // query's bound of q moves r by up to that over n . (q - p) = |q - p|^2 / (2 r_new).
      shrink_error[i] = q[k].bound * 2.0 * r_new * r_new / glm::dot(e, e);
      next.push_back(i);
    }
    active.swap(next);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    if (radius[i] > 0.0) out[i].thickness = 2.0 * radius[i];
    f.unconverged += radius[i] > 0.0 && !out[i].converged;
  }
  if (figures) *figures = f;
  return out;
}

}  // namespace nurbs::ray
