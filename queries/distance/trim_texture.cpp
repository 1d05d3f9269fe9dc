#include "queries/distance/trim_texture.h"

#include <algorithm>
#include <cmath>

#include "gpgpu/polygon_fill.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/surface_grid.h"

namespace queries {
namespace {

/// The map from a parameter to the window coordinate of the grid (sample i at i + 0.5): linear on
/// each run of equal steps ("piece"), continuous, extended linearly beyond the ends.
class WindowMap {
 public:
  explicit WindowMap(const std::vector<double>& t) {
    size_t start = 0;
    for (size_t i = 1; i + 1 < t.size(); ++i) {
      const double a = t[i] - t[i - 1], b = t[i + 1] - t[i];
      if (std::abs(a - b) > 1e-9 * std::max(a, b)) {  // the step changes at sample i
        add(t, start, i);
        start = i;
      }
    }
    add(t, start, t.size() - 1);
  }
  [[nodiscard]] double operator()(double t) const {
    auto it = std::upper_bound(starts_.begin(), starts_.end(), t);
    const size_t k = it == starts_.begin() ? 0 : size_t(it - starts_.begin()) - 1;
    return index_[k] + (t - starts_[k]) * scale_[k] + 0.5;
  }
  /// Interior piece ends, where edges must be split.
  [[nodiscard]] std::vector<double> breaks() const { return {starts_.begin() + 1, starts_.end()}; }

 private:
  void add(const std::vector<double>& t, size_t from, size_t to) {
    starts_.push_back(t[from]);
    index_.push_back(double(from));
    scale_.push_back(double(to - from) / (t[to] - t[from]));
  }
  std::vector<double> starts_, index_, scale_;
};

/// Edge p -> q split at every break of either direction it crosses (fractions in (0, 1)), appended
/// to `out` without q.
void split_edge(glm::dvec2 p, glm::dvec2 q, const std::vector<double>& bu, const std::vector<double>& bv,
                std::vector<glm::dvec2>& out) {
  out.push_back(p);
  std::vector<double> at;
  auto crossings = [&](const std::vector<double>& br, double a, double b) {
    if (a == b) return;
    auto lo = std::upper_bound(br.begin(), br.end(), std::min(a, b));
    for (auto it = lo; it != br.end() && *it < std::max(a, b); ++it) at.push_back((*it - a) / (b - a));
  };
  crossings(bu, p.x, q.x);
  crossings(bv, p.y, q.y);
  std::sort(at.begin(), at.end());
  for (double s : at) out.push_back(p + s * (q - p));
}

/// The face's loops in (u, v), split at the grid's piece ends, with the domain rectangle added as
/// outer boundary when the face has none.
std::vector<std::vector<glm::dvec2>> split_loops(const nurbs::TrimPolygons& trim, const WindowMap& mu,
                                                 const WindowMap& mv, const nurbs::ParamGrid& params) {
  const std::vector<double> bu = mu.breaks(), bv = mv.breaks();
  std::vector<std::vector<glm::dvec2>> loops;
  bool has_outer = false;
  for (size_t k = 0; k < trim.loops.size(); ++k) {
    has_outer = has_outer || trim.outer[k];
    std::vector<glm::dvec2> poly;
    const auto& loop = trim.loops[k];
    for (size_t i = 0; i < loop.size(); ++i) split_edge(loop[i], loop[(i + 1) % loop.size()], bu, bv, poly);
    loops.push_back(std::move(poly));
  }
  if (!has_outer) {  // the domain rectangle, a little larger, covers every sample
    const double du = params.u.back() - params.u.front(), dv = params.v.back() - params.v.front();
    const double u0 = params.u.front() - du, u1 = params.u.back() + du;
    const double v0 = params.v.front() - dv, v1 = params.v.back() + dv;
    loops.push_back({{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}});
  }
  return loops;
}

}  // namespace

std::vector<std::vector<glm::vec2>> trim_window_polygons(const nurbs::TrimmedSurface& face,
                                                         const nurbs::ParamGrid& params, double flatten_tolerance) {
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, flatten_tolerance);
  const WindowMap mu(params.u), mv(params.v);
  std::vector<std::vector<glm::vec2>> polygons;
  for (const auto& loop : split_loops(trim, mu, mv, params)) {
    std::vector<glm::vec2> poly;
    poly.reserve(loop.size());
    for (const glm::dvec2& p : loop) poly.emplace_back(float(mu(p.x)), float(mv(p.y)));
    polygons.push_back(std::move(poly));
  }
  return polygons;
}

std::vector<gpgpu::Texture> trim_masks(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face,
                                       const nurbs::ParamGrid& params, int tile_side, double flatten_tolerance) {
  const auto window = trim_window_polygons(face, params, flatten_tolerance);
  const int W = static_cast<int>(params.u.size()), H = static_cast<int>(params.v.size());
  std::vector<gpgpu::Texture> masks;
  for (int j0 : tile_starts(H, tile_side)) {
    for (int i0 : tile_starts(W, tile_side)) {
      std::vector<std::vector<glm::vec2>> polygons = window;
      for (auto& poly : polygons)
        for (glm::vec2& v : poly) v -= glm::vec2(float(i0), float(j0));
      gpgpu::Texture mask(std::min(tile_side, W - i0), std::min(tile_side, H - j0), gpgpu::Format::R8);
      gpgpu::fill_polygons_even_odd(gpu, polygons, mask);
      gpu.dump("trim_mask", mask);
      masks.push_back(std::move(mask));
    }
  }
  return masks;
}

gpgpu::Texture trim_texture(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, const nurbs::ParamGrid& params,
                            double flatten_tolerance) {
  const int side = static_cast<int>(std::max(params.u.size(), params.v.size()));
  return std::move(trim_masks(gpu, face, params, side, flatten_tolerance).front());
}

gpgpu::Texture trim_texture(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, int n, int m,
                            double flatten_tolerance) {
  const auto params =
      nurbs::uniform_param_grid(nurbs::surface_domain_u(face.surface), nurbs::surface_domain_v(face.surface), n, m);
  return trim_texture(gpu, face, params, flatten_tolerance);
}

std::vector<uint8_t> trim_mask_cpu(const nurbs::TrimmedSurface& face, const nurbs::ParamGrid& params,
                                   double flatten_tolerance) {
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, flatten_tolerance);
  std::vector<uint8_t> mask;
  mask.reserve(size_t(params.samples()));
  for (double v : params.v)
    for (double u : params.u) mask.push_back(nurbs::is_material(trim, {u, v}) ? 1 : 0);
  return mask;
}

std::vector<uint8_t> trim_mask_cpu(const nurbs::TrimmedSurface& face, int n, int m, double flatten_tolerance) {
  const auto params =
      nurbs::uniform_param_grid(nurbs::surface_domain_u(face.surface), nurbs::surface_domain_v(face.surface), n, m);
  return trim_mask_cpu(face, params, flatten_tolerance);
}

}  // namespace queries
