#include "nurbs/homogeneous.h"

namespace nurbs {

template <int D>
HomogeneousCurve to_homogeneous(const Curve<D>& curve) {
  HomogeneousCurve h{curve.degree, curve.knots, {}};
  h.points.resize(curve.points.size());
  for (size_t i = 0; i < curve.points.size(); ++i) {
    const double w = curve.rational() ? curve.weights[i] : 1.0;
    glm::dvec4 p(0.0, 0.0, 0.0, w);
    for (int k = 0; k < D; ++k) p[k] = w * curve.points[i][k];
    h.points[i] = p;
  }
  return h;
}

template <int D>
Curve<D> from_homogeneous(const HomogeneousCurve& h, bool rational) {
  Curve<D> c;
  c.degree = h.degree;
  c.knots = h.knots;
  c.points.resize(h.points.size());
  if (rational) c.weights.resize(h.points.size());
  for (size_t i = 0; i < h.points.size(); ++i) {
    const double w = h.points[i].w;
    for (int k = 0; k < D; ++k) c.points[i][k] = h.points[i][k] / w;
    if (rational) c.weights[i] = w;
  }
  return c;
}

template HomogeneousCurve to_homogeneous(const Curve<2>&);
template HomogeneousCurve to_homogeneous(const Curve<3>&);
template Curve<2> from_homogeneous<2>(const HomogeneousCurve&, bool);
template Curve<3> from_homogeneous<3>(const HomogeneousCurve&, bool);

std::vector<double> reversed_knots(const std::vector<double>& knots) {
  std::vector<double> r(knots.rbegin(), knots.rend());
  const double sum = knots.front() + knots.back();
  for (double& k : r) k = sum - k;
  return r;
}

HomogeneousCurve reversed(const HomogeneousCurve& h) {
  return {h.degree, reversed_knots(h.knots), std::vector<glm::dvec4>(h.points.rbegin(), h.points.rend())};
}

namespace {
glm::dvec4 homogeneous_point(const Surface& s, int i, int j) {
  const double w = s.weight(i, j);
  return {w * s.point(i, j), w};
}
}  // namespace

HomogeneousCurve surface_row(const Surface& s, int j) {
  HomogeneousCurve h{s.degree_u, s.knots_u, {}};
  h.points.reserve(static_cast<size_t>(s.count_u));
  for (int i = 0; i < s.count_u; ++i) h.points.push_back(homogeneous_point(s, i, j));
  return h;
}

HomogeneousCurve surface_column(const Surface& s, int i) {
  HomogeneousCurve h{s.degree_v, s.knots_v, {}};
  h.points.reserve(static_cast<size_t>(s.count_v));
  for (int j = 0; j < s.count_v; ++j) h.points.push_back(homogeneous_point(s, i, j));
  return h;
}

namespace {
void store(Surface& s, int i, int j, const glm::dvec4& p, bool rational) {
  const size_t k = static_cast<size_t>(j) * static_cast<size_t>(s.count_u) + static_cast<size_t>(i);
  s.points[k] = glm::dvec3(p) / p.w;
  if (rational) s.weights[k] = p.w;
}
}  // namespace

Surface surface_from_rows(const std::vector<HomogeneousCurve>& rows, const Surface& like, bool rational) {
  Surface s;
  s.degree_u = rows.front().degree;
  s.knots_u = rows.front().knots;
  s.count_u = static_cast<int>(rows.front().points.size());
  s.degree_v = like.degree_v;
  s.knots_v = like.knots_v;
  s.count_v = static_cast<int>(rows.size());
  s.points.resize(static_cast<size_t>(s.count_u) * static_cast<size_t>(s.count_v));
  if (rational) s.weights.resize(s.points.size());
  for (int j = 0; j < s.count_v; ++j) {
    for (int i = 0; i < s.count_u; ++i)
      store(s, i, j, rows[static_cast<size_t>(j)].points[static_cast<size_t>(i)], rational);
  }
  return s;
}

Surface surface_from_columns(const std::vector<HomogeneousCurve>& cols, const Surface& like, bool rational) {
  Surface s;
  s.degree_v = cols.front().degree;
  s.knots_v = cols.front().knots;
  s.count_v = static_cast<int>(cols.front().points.size());
  s.degree_u = like.degree_u;
  s.knots_u = like.knots_u;
  s.count_u = static_cast<int>(cols.size());
  s.points.resize(static_cast<size_t>(s.count_u) * static_cast<size_t>(s.count_v));
  if (rational) s.weights.resize(s.points.size());
  for (int i = 0; i < s.count_u; ++i) {
    for (int j = 0; j < s.count_v; ++j)
      store(s, i, j, cols[static_cast<size_t>(i)].points[static_cast<size_t>(j)], rational);
  }
  return s;
}

}  // namespace nurbs
