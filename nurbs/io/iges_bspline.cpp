// IGES 126 (rational B-spline curve, spec §4.23) and 128 (rational B-spline surface, §4.24).
#include <fmt/format.h>

#include <algorithm>

#include "nurbs/io/iges_geometry.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/read_error.h"
#include "nurbs/restrict.h"
#include "nurbs/validate.h"

namespace nurbs::io {
namespace {

// Knots at parameters first..first+count-1: non-decreasing, no knot repeated more than degree + 1
// times, and a non-empty domain [knots[degree], knots[count - degree - 1]].
std::vector<double> read_knots(const EntityParams& p, int first, int count, int degree, const char* dir) {
  std::vector<double> k(static_cast<size_t>(count));
  int multiplicity = 1;
  for (int i = 0; i < count; ++i) {
    k[static_cast<size_t>(i)] = p.real(first + i);
    if (i == 0) continue;
    const double prev = k[static_cast<size_t>(i - 1)], cur = k[static_cast<size_t>(i)];
    if (cur < prev)
      p.fail(first + i, fmt::format("{}knot {} ({}) is less than knot {} ({}): knots must be non-decreasing", dir, i,
                                    cur, i - 1, prev));
    multiplicity = cur == prev ? multiplicity + 1 : 1;
    if (multiplicity > degree + 1)
      p.fail(first + i, fmt::format("{}knot {} is repeated {} times, more than degree + 1 = {}", dir, cur, multiplicity,
                                    degree + 1));
  }
  if (!(k[static_cast<size_t>(degree)] < k[static_cast<size_t>(count - degree - 1)]))
    p.fail(first, fmt::format("{}knot vector has an empty domain [{}, {}]", dir, k[static_cast<size_t>(degree)],
                              k[static_cast<size_t>(count - degree - 1)]));
  return k;
}

// Weights at parameters first..first+count-1, all > 0; empty when all are equal (polynomial).
std::vector<double> read_weights(const EntityParams& p, int first, int count) {
  std::vector<double> w(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    w[static_cast<size_t>(i)] = p.real(first + i);
    if (!(w[static_cast<size_t>(i)] > 0.0))
      p.fail(first + i, fmt::format("weight {} is {}, weights must be > 0", i, w[static_cast<size_t>(i)]));
  }
  if (std::all_of(w.begin(), w.end(), [&](double x) { return x == w.front(); })) w.clear();
  return w;
}

// Number of parameters an entity needs, computed in 64 bits and checked before any allocation so
// that a huge count in a malformed file fails cleanly instead of exhausting memory.
void require_count(const EntityParams& p, long long needed) {
  if (needed > p.size())
    p.fail(p.size(),
           fmt::format("bad parameter count: the counts and degrees in the record need {} parameters, it has {}",
                       needed, p.size()));
}

// Last line of defence after the field-level checks: the core's own validation (nurbs/validate.h),
// then the reader's limit on magnitudes (kMaxCoordinate).
template <class T>
void check_valid(const EntityParams& p, const T& geometry) {
  std::vector<std::string> problems = validate(geometry);
  if (!problems.empty()) p.fail(0, "invalid geometry: " + problems.front());
  problems = validate_magnitude(geometry, kMaxCoordinate);
  if (!problems.empty()) p.fail(0, "out of range: " + problems.front());
}

// A degree field in [1, kMaxDegree] (and at most the record size, which bounds any sane count).
int read_degree(const EntityParams& p, int i, const char* what) {
  const int m = p.integer(i);
  if (m > kMaxDegree)
    p.fail(i, fmt::format("{} = {} exceeds the largest degree nurbsgl reads, {}", what, m, kMaxDegree));
  return p.integer(i, 1, p.size(), what);
}

/// True when [a, b] cuts off more than rounding (1e-9 of the width) at either end of `domain`.
bool inside(Interval domain, double a, double b) {
  const double eps = 1e-9 * domain.width();
  return a > domain.min + eps || b < domain.max - eps;
}

}  // namespace

Curve3 IgesGeometry::bspline_curve(const EntityParams& p) {
  const int k = p.integer(1, 1, p.size(), "upper index K");
  const int m = read_degree(p, 2, "degree M");
  if (k < m) p.fail(1, fmt::format("upper index K = {} is less than degree M = {} (too few control points)", k, m));
  for (int i = 3; i <= 6; ++i) p.integer(i, 0, 1, "property flag");
  const int n = k + 1;
  const int nk = n + m + 1;
  const int w0 = 7 + nk, p0 = w0 + n, v0 = p0 + 3 * n;
  require_count(p, 6LL + nk + n + 3LL * n + 2);
  Curve3 c;
  c.degree = m;
  c.knots = read_knots(p, 7, nk, m, "");
  c.weights = read_weights(p, w0, n);
  c.points.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    c.points[static_cast<size_t>(i)] = {p.real(p0 + 3 * i), p.real(p0 + 3 * i + 1), p.real(p0 + 3 * i + 2)};
  const double a = p.real(v0), b = p.real(v0 + 1);
  if (!(a < b)) p.fail(v0, fmt::format("parameter range V(0) = {} is not less than V(1) = {}", a, b));
  // The unit normal of planar curves follows; writers of non-planar curves sometimes leave it out.
  int used = v0 + 1;
  if (p.size() >= v0 + 4) {
    for (int i = 2; i <= 4; ++i) (void)p.real(v0 + i);
    used = v0 + 4;
  }
  p.check_trailing(used);
  check_valid(p, c);
  // IGES: the curve is its part on [V(0), V(1)]; restrict when that is inside the knot domain.
  const Interval dom = knot_domain(c.knots, c.degree, static_cast<int>(c.points.size()));
  if (inside(dom, a, b)) {
    c = restrict_curve(c, a, b);
    ++ranges_restricted_;
  }
  return c;
}

Surface IgesGeometry::surface(int de, const glm::dmat4& parent, bool restrict_to_range) {
  const IgesDirectoryEntry& e = file_.entry(de);
  if (e.type != 128) fail(de, "is not a rational B-spline surface (128)");
  const glm::dmat4 xf = parent * transform(de);
  EntityParams p(file_, e);
  const int k1 = p.integer(1, 1, p.size(), "upper index K1");
  const int k2 = p.integer(2, 1, p.size(), "upper index K2");
  const int m1 = read_degree(p, 3, "degree M1");
  const int m2 = read_degree(p, 4, "degree M2");
  if (k1 < m1) p.fail(1, fmt::format("upper index K1 = {} is less than degree M1 = {}", k1, m1));
  if (k2 < m2) p.fail(2, fmt::format("upper index K2 = {} is less than degree M2 = {}", k2, m2));
  for (int i = 5; i <= 9; ++i) p.integer(i, 0, 1, "property flag");
  const int nu = k1 + 1, nv = k2 + 1;
  const long long count = static_cast<long long>(nu) * nv;
  const long long needed = 9LL + (nu + m1 + 1) + (nv + m2 + 1) + 4 * count + 4;
  require_count(p, needed);
  points_made_ += count;
  check_point_budget(de);  // a surface shared by many faces is copied for each
  const int ku = 10, kv = ku + nu + m1 + 1, w0 = kv + nv + m2 + 1, p0 = w0 + static_cast<int>(count);
  Surface s;
  s.degree_u = m1;
  s.degree_v = m2;
  s.count_u = nu;
  s.count_v = nv;
  s.knots_u = read_knots(p, ku, nu + m1 + 1, m1, "u ");
  s.knots_v = read_knots(p, kv, nv + m2 + 1, m2, "v ");
  s.weights = read_weights(p, w0, static_cast<int>(count));
  // Control points are stored with the first index (u) fastest, as in nurbs::Surface.
  s.points.resize(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const glm::dvec3 q(p.real(p0 + 3 * i), p.real(p0 + 3 * i + 1), p.real(p0 + 3 * i + 2));
    s.points[static_cast<size_t>(i)] = glm::dvec3(xf * glm::dvec4(q, 1.0));
  }
  const int r0 = p0 + 3 * static_cast<int>(count);
  const double u0 = p.real(r0), u1 = p.real(r0 + 1), v0 = p.real(r0 + 2), v1 = p.real(r0 + 3);
  p.check_trailing(r0 + 3);
  check_valid(p, s);
  // IGES: the surface is its part on [U(0), U(1)] x [V(0), V(1)]; restrict when inside the domain.
  // An empty range (a writer's rounding: FreeCAD wrote U(0) = U(1) on a knot span of 3e-7) says
  // nothing of the part: the knot domain is kept, as OpenCASCADE keeps it, with a warning.
  const bool empty = !(u0 < u1) || !(v0 < v1);
  if (empty) {
    warnings_.push_back(fmt::format("{}: parameter range [{}, {}] x [{}, {}] is empty; its knot domain is used",
                                    p.where(r0), u0, u1, v0, v1));
  }
  const Interval du = knot_domain(s.knots_u, s.degree_u, s.count_u), dv = knot_domain(s.knots_v, s.degree_v, s.count_v);
  if (restrict_to_range && !empty && (inside(du, u0, u1) || inside(dv, v0, v1))) {
    s = restrict_surface(s, {u0, u1}, {v0, v1});
    ++ranges_restricted_;
  }
  return s;
}

}  // namespace nurbs::io
