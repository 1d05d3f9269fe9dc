#include "queries/inspection/best_fit.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "nurbs/surface_eval.h"

namespace queries {
namespace {

/// Tukey's biweight constant (95 % efficiency at the normal distribution) and the median absolute
/// value's factor to the normal's sigma.
constexpr double kTukey = 4.685, kMadToSigma = 1.4826;

/// The rotation by the vector `w` (axis times angle, Rodrigues) and translation `t` as a matrix.
glm::dmat4 motion(const glm::dvec3& w, const glm::dvec3& t) {
  glm::dmat4 m(1.0);
  const double angle = glm::length(w);
  if (angle > 0.0) m = glm::rotate(m, angle, w / angle);
  m[3] = glm::dvec4(t, 1.0);
  return m;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + long(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

double tukey_reach(std::vector<double> residuals, double floor) {
  for (double& r : residuals) r = std::abs(r);
  return kTukey * std::max(kMadToSigma * median(std::move(residuals)), floor);
}

glm::dvec3 apply(const glm::dmat4& matrix, const glm::dvec3& p) { return glm::dvec3(matrix * glm::dvec4(p, 1.0)); }

bool rigid_motion(const glm::dmat4& m, std::string* why) {
  auto fail = [&](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return fail("a number is not finite");
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) return fail("its last row is not 0 0 0 1");
  const glm::dmat3 r(m);
  const glm::dmat3 rtr = glm::transpose(r) * r;
  double off = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) off = std::max(off, std::abs(rtr[c][k] - (c == k ? 1.0 : 0.0)));
  if (off > 1e-6) return fail(fmt::format("its 3 x 3 part is not a rotation (R^T R differs from I by {:.3g})", off));
  if (glm::determinant(r) < 0.0) return fail("its 3 x 3 part is a reflection (determinant -1), not a rotation");
  return true;
}

Alignment best_fit(PointQuery& query, std::span<const glm::dvec3> scan, const BestFitOptions& o) {
  const std::vector<nurbs::TrimmedSurface>& faces = query.faces();
  if (o.sample == 0) throw nurbs::RequestError("best fit: sample must be at least 1 point");
  if (o.max_iterations < 1) throw nurbs::RequestError("best fit: max_iterations must be at least 1");
  if (!(o.max_distance > 0.0)) throw nurbs::RequestError("best fit: max_distance must be positive");
  for (const int f : o.faces)
    if (f < 0 || size_t(f) >= faces.size())
      throw nurbs::RequestError(
          fmt::format("best fit: face {} is not a face of the model (0 to {})", f, faces.size() - 1));
  std::string why;
  if (!rigid_motion(o.start, &why)) throw nurbs::RequestError("best fit: the start is not a rigid motion: " + why);
  if (scan.empty()) throw nurbs::RequestError("best fit: no points");
  std::vector<char> fit_face(faces.size(), o.faces.empty() ? 1 : 0);
  for (const int f : o.faces) fit_face[size_t(f)] = 1;

  // The sample, spread evenly over the scan.
  std::vector<glm::dvec3> sample;
  const size_t n = std::min(o.sample, scan.size());
  sample.reserve(n);
  for (size_t k = 0; k < n; ++k) sample.push_back(scan[k * scan.size() / n]);

  Alignment a;
  a.matrix = o.start;
  const double tolerance = query.tolerance();
  const double step = o.step > 0.0 ? o.step : 1e-3 * tolerance;
  if (o.coarse_start) {
    // Far off: the sample's median distance to the model above a tenth of its size. The fit then
    // starts from the translation between the box centres: the model's faces' and the sample's
    // between its 2nd and 98th percentiles per axis (outliers do not move it).
    std::vector<glm::dvec3> start(n);
    for (size_t k = 0; k < n; ++k) start[k] = apply(a.matrix, sample[k]);
    std::vector<double> distance;
    for (const PointDistance& d : query.query(start).answers)
      distance.push_back(d.found ? d.distance : std::numeric_limits<double>::infinity());
    if (median(distance) > 0.1 * query.model_size()) {
      nurbs::Box model;
      bool first = true;
      for (const nurbs::TrimmedSurface& f : faces) {
        const nurbs::Box b = nurbs::sampled_box(f.surface);
        model.min = first ? b.min : glm::min(model.min, b.min), model.max = first ? b.max : glm::max(model.max, b.max);
        first = false;
      }
      glm::dvec3 centre;
      for (int axis = 0; axis < 3; ++axis) {
        std::vector<double> c;
        for (const glm::dvec3& p : start) c.push_back(p[axis]);
        const auto lo = c.begin() + long(0.02 * double(n)), hi = c.begin() + long(0.98 * double(n - 1));
        std::nth_element(c.begin(), lo, c.end());
        const double low = *lo;
        std::nth_element(c.begin(), hi, c.end());
        centre[axis] = 0.5 * (low + *hi);
      }
      a.matrix = motion(glm::dvec3(0.0), 0.5 * (model.min + model.max) - centre) * a.matrix;
      a.coarse_start = true;
    }
  }
  std::vector<glm::dvec3> moved(n);
  std::vector<double> residual;
  for (a.iterations = 1; a.iterations <= o.max_iterations; ++a.iterations) {
    for (size_t k = 0; k < n; ++k) moved[k] = apply(a.matrix, sample[k]);
    const PointQueryResult r = query.query(moved);
    // Pairs: the moved point, its closest point's outward normal, the signed residual along it.
    struct Pair {
      glm::dvec3 p, normal;
      double e;
    };
    std::vector<Pair> pairs;
    residual.clear();
    for (size_t k = 0; k < n; ++k) {
      const PointDistance& d = r.answers[k];
      if (!d.found || d.distance > o.max_distance || !fit_face[size_t(d.face)]) continue;
      const glm::dvec3 normal = r.normals[k];
      if (!(glm::length(normal) > 0.5)) continue;  // a degenerate point (a pole)
      pairs.push_back({moved[k], normal, glm::dot(moved[k] - d.point, normal)});
      residual.push_back(pairs.back().e);
    }
    if (pairs.size() < 6) {
      a.problem = fmt::format(
          "{} of the {} sampled points lie within the maximum distance of the fitted faces; "
          "6 are needed",
          pairs.size(), n);
      break;
    }
    const double reach = tukey_reach(residual, tolerance);
    // Rotations about the pairs' centre: the equations stay well scaled far from the origin.
    glm::dvec3 centre(0.0);
    for (const Pair& q : pairs) centre += q.p / double(pairs.size());
    Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
    double sw = 0.0, swe2 = 0.0;
    long long used = 0;
    for (const Pair& q : pairs) {
      const double w = tukey_weight(q.e, reach);
      if (w == 0.0) continue;
      const glm::dvec3 pn = glm::cross(q.p - centre, q.normal);
      Eigen::Matrix<double, 6, 1> j;
      j << pn.x, pn.y, pn.z, q.normal.x, q.normal.y, q.normal.z;
      ata += w * j * j.transpose();
      atb -= w * q.e * j;
      sw += w, swe2 += w * q.e * q.e;
      ++used;
    }
    a.points_used = used;
    a.rms = sw > 0.0 ? std::sqrt(swe2 / sw) : 0.0;
    if (used < 6) {
      a.problem = "fewer than 6 points within the robust weight's reach";
      break;
    }
    // Motions the faces do not hold (a sphere's rotations, a torus's about its axis) stay put: the
    // equations are solved in their eigenvectors, those of eigenvalues below 1e-9 of the largest
    // left out, instead of letting noise slide the scan along them.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(ata);
    const double largest = eigen.eigenvalues().maxCoeff();
    Eigen::Matrix<double, 6, 1> x = Eigen::Matrix<double, 6, 1>::Zero();
    for (int i = 0; i < 6; ++i) {
      const double lambda = eigen.eigenvalues()[i];
      if (lambda > 1e-9 * largest) x += (eigen.eigenvectors().col(i).dot(atb) / lambda) * eigen.eigenvectors().col(i);
    }
    if (!x.allFinite()) {
      a.problem = "the fit's equations are singular (the fitted faces do not hold the scan in every direction)";
      break;
    }
    const glm::dvec3 w(x[0], x[1], x[2]), t(x[3], x[4], x[5]);
    const glm::dmat4 delta =
        motion(glm::dvec3(0.0), centre + t) * motion(w, glm::dvec3(0.0)) * motion(glm::dvec3(0.0), -centre);
    double moved_most = 0.0;
    for (const Pair& q : pairs) moved_most = std::max(moved_most, glm::length(apply(delta, q.p) - q.p));
    a.matrix = delta * a.matrix;
    if (moved_most <= step) {
      a.converged = true;
      break;
    }
  }
  a.iterations = std::min(a.iterations, o.max_iterations);
  if (!a.converged && a.problem.empty())
    a.problem =
        fmt::format("no convergence in {} rounds (the last moved points more than {:.3g})", o.max_iterations, step);
  return a;
}

}  // namespace queries
