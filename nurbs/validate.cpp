#include "nurbs/validate.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "nurbs/knot_vector.h"

namespace nurbs {
namespace {

void append_prefixed(std::vector<std::string>& out, const std::vector<std::string>& in, const char* prefix) {
  for (const auto& s : in) out.push_back(fmt::format("{}{}", prefix, s));
}

void check_weights(std::vector<std::string>& out, const std::vector<double>& weights, size_t expected) {
  if (weights.empty()) return;
  if (weights.size() != expected) {
    out.push_back(fmt::format("{} weights for {} control points", weights.size(), expected));
    return;
  }
  for (size_t i = 0; i < weights.size(); ++i) {
    if (!std::isfinite(weights[i]) || !(weights[i] > 0.0)) {
      out.push_back(fmt::format("weight {} is {} (must be finite and > 0)", i, weights[i]));
    }
  }
}

template <typename P>
void check_points(std::vector<std::string>& out, const std::vector<P>& points) {
  for (size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < P::length(); ++k) {
      if (!std::isfinite(points[i][k])) {
        out.push_back(fmt::format("control point {} is not finite", i));
        break;
      }
    }
  }
}

void check_knot_magnitude(std::vector<std::string>& out, const std::vector<double>& knots, double limit,
                          const char* prefix) {
  for (size_t i = 0; i < knots.size(); ++i)
    if (!(std::fabs(knots[i]) <= limit)) {
      out.push_back(fmt::format("{}knot {} is {:g}, beyond the largest magnitude {:g}", prefix, i, knots[i], limit));
      return;
    }
}

template <typename P>
void check_magnitudes(std::vector<std::string>& out, const std::vector<P>& points, const std::vector<double>& weights,
                      double limit) {
  for (size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < P::length(); ++k)
      if (!(std::fabs(points[i][k]) <= limit)) {
        out.push_back(fmt::format("control point {} has coordinate {:g}, beyond the largest magnitude {:g}", i,
                                  points[i][k], limit));
        i = points.size();
        break;
      }
  for (size_t i = 0; i < weights.size(); ++i)
    if (!(weights[i] <= limit && weights[i] >= 1.0 / limit)) {
      out.push_back(fmt::format("weight {} is {:g}, outside [{:g}, {:g}]", i, weights[i], 1.0 / limit, limit));
      return;
    }
  if (weights.empty()) return;
  const auto [lo, hi] = std::minmax_element(weights.begin(), weights.end());
  if (*hi > kMaxWeightRatio * *lo)
    out.push_back(fmt::format("weight {} is {:g} and weight {} is {:g}: a ratio of {:.3g}, above the {:g} that "
                              "the rational bounds carry",
                              hi - weights.begin(), *hi, lo - weights.begin(), *lo, *hi / *lo, kMaxWeightRatio));
}

}  // namespace

template <int D>
std::vector<std::string> validate_magnitude(const Curve<D>& curve, double limit) {
  std::vector<std::string> out;
  check_knot_magnitude(out, curve.knots, limit, "");
  check_magnitudes(out, curve.points, curve.weights, limit);
  return out;
}

template std::vector<std::string> validate_magnitude(const Curve<2>&, double);
template std::vector<std::string> validate_magnitude(const Curve<3>&, double);

std::vector<std::string> validate_magnitude(const Surface& s, double limit) {
  std::vector<std::string> out;
  check_knot_magnitude(out, s.knots_u, limit, "u ");
  check_knot_magnitude(out, s.knots_v, limit, "v ");
  check_magnitudes(out, s.points, s.weights, limit);
  return out;
}

template <int D>
std::vector<std::string> validate(const Curve<D>& curve) {
  std::vector<std::string> out;
  append_prefixed(out, validate_knots(curve.knots, curve.degree, static_cast<int>(curve.points.size())), "knots: ");
  check_weights(out, curve.weights, curve.points.size());
  check_points(out, curve.points);
  return out;
}

template std::vector<std::string> validate(const Curve<2>&);
template std::vector<std::string> validate(const Curve<3>&);

std::vector<std::string> validate(const Surface& s) {
  std::vector<std::string> out;
  append_prefixed(out, validate_knots(s.knots_u, s.degree_u, s.count_u), "knots_u: ");
  append_prefixed(out, validate_knots(s.knots_v, s.degree_v, s.count_v), "knots_v: ");
  const size_t expected = s.count_u > 0 && s.count_v > 0 ? static_cast<size_t>(s.count_u) * s.count_v : 0;
  if (s.points.size() != expected) {
    out.push_back(fmt::format("{} control points, expected count_u * count_v = {}", s.points.size(), expected));
  }
  check_weights(out, s.weights, s.points.size());
  check_points(out, s.points);
  return out;
}

}  // namespace nurbs
