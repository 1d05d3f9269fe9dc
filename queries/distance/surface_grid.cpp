#include "queries/distance/surface_grid.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <stdexcept>
#include <string>

#include "gpgpu/array_texture.h"
#include "nurbs/knot_vector.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/shaders.h"

namespace queries {
namespace {

gpgpu::Texture normalised_knots(const std::vector<double>& knots, nurbs::Interval domain, int max_size) {
  std::vector<float> k(knots.size());
  for (size_t i = 0; i < knots.size(); ++i) k[i] = static_cast<float>((knots[i] - domain.min) / domain.width());
  return gpgpu::upload_array_pow2(k, gpgpu::Format::R32F, max_size, 0.0f).texture;
}

/// Parameters [first, first + count) of one direction, normalised to the domain, as an R32F row.
gpgpu::Texture normalised_params(const std::vector<double>& t, int first, int count, nurbs::Interval domain) {
  std::vector<float> p(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i)
    p[size_t(i)] = static_cast<float>((t[size_t(first + i)] - domain.min) / domain.width());
  gpgpu::Texture tex(count, 1, gpgpu::Format::R32F);
  tex.upload(p);
  return tex;
}

gpgpu::Texture basis_table(const std::vector<double>& knots, int degree, int count, const std::vector<double>& t,
                           int first, int samples, nurbs::Interval domain) {
  gpgpu::Texture tex(samples, degree + 1, gpgpu::Format::RGBA32F);
  tex.upload(tabulate_basis(knots, degree, count, t, first, samples, domain));
  return tex;
}

/// Evaluates one tile into `tile` (whose textures are allocated to its size).
void evaluate_tile(gpgpu::Gpu& gpu, const GpuSurface& s, const nurbs::ParamGrid& params, GridTile& tile,
                   EvalMethod method) {
  const int w = tile.points.width(), h = tile.points.height();
  gpgpu::Texture* outputs[] = {&tile.points, &tile.normals};
  const glm::vec3 origin(s.origin);
  if (method == EvalMethod::PerFragment) {
    const gpgpu::Texture pu = normalised_params(params.u, tile.i0, w, s.domain_u);
    const gpgpu::Texture pv = normalised_params(params.v, tile.j0, h, s.domain_v);
    gpgpu::Program& p =
        queries::program(gpu, "surface_eval.frag", {{"MAX_DEGREE", std::to_string(std::max(s.degree_u, s.degree_v))}});
    p.set("u_count", s.count_u, s.count_v);
    p.set("u_degree", s.degree_u, s.degree_v);
    p.set("u_origin", origin.x, origin.y, origin.z);
    const gpgpu::Input inputs[] = {{"u_knots_u", &s.knots_u},
                                   {"u_knots_v", &s.knots_v},
                                   {"u_ctrl", &s.control},
                                   {"u_params_u", &pu},
                                   {"u_params_v", &pv}};
    gpu.run("surface_eval", p, inputs, outputs);
  } else {
    const gpgpu::Texture bu = basis_table(s.host_knots_u, s.degree_u, s.count_u, params.u, tile.i0, w, s.domain_u);
    const gpgpu::Texture bv = basis_table(s.host_knots_v, s.degree_v, s.count_v, params.v, tile.j0, h, s.domain_v);
    gpgpu::Program& p = queries::program(gpu, "surface_eval_tabulated.frag");
    p.set("u_count_u", s.count_u);
    p.set("u_degree", s.degree_u, s.degree_v);
    p.set("u_origin", origin.x, origin.y, origin.z);
    const gpgpu::Input inputs[] = {{"u_basis_u", &bu}, {"u_basis_v", &bv}, {"u_ctrl", &s.control}};
    gpu.run("surface_eval_tabulated", p, inputs, outputs);
  }
}

std::vector<float> read_all(const SurfaceGrid& g, bool normals) {
  const size_t W = g.params.u.size(), H = g.params.v.size();
  std::vector<float> out(W * H * 4);
  for (const GridTile& t : g.tiles) {
    const gpgpu::Texture& tex = normals ? t.normals : t.points;
    const std::vector<float> data = tex.read();
    for (int y = 0; y < tex.height(); ++y)
      std::copy_n(data.begin() + ptrdiff_t(y) * tex.width() * 4, size_t(tex.width()) * 4,
                  out.begin() + ptrdiff_t((size_t(t.j0 + y) * W + size_t(t.i0)) * 4));
  }
  return out;
}

}  // namespace

std::vector<float> tabulate_basis(const std::vector<double>& knots, int degree, int count, const std::vector<double>& t,
                                  int first, int samples, nurbs::Interval domain) {
  const int w = degree + 1;
  std::vector<float> table(size_t(samples) * size_t(w) * 4);
  std::vector<double> nd(size_t(2 * w));
  for (int i = 0; i < samples; ++i) {
    const double u = t[size_t(first + i)];
    const int span = nurbs::find_span(knots, degree, count, u);
    nurbs::basis_function_derivatives(knots, degree, span, u, 1, nd.data());
    for (int r = 0; r < w; ++r) {
      float* texel = &table[(size_t(r) * size_t(samples) + size_t(i)) * 4];
      texel[0] = static_cast<float>(nd[size_t(r)]);
      texel[1] = static_cast<float>(nd[size_t(w + r)] * domain.width());
      texel[2] = static_cast<float>(span);
      texel[3] = 0.0f;
    }
  }
  return table;
}

std::vector<int> tile_starts(int samples, int side) {
  std::vector<int> starts{0};
  while (starts.back() + side < samples) starts.push_back(starts.back() + side - 1);
  return starts;
}

GpuSurface upload_surface(const nurbs::Surface& s, int max_texture_size) {
  GpuSurface g;
  g.count_u = s.count_u;
  g.count_v = s.count_v;
  g.degree_u = s.degree_u;
  g.degree_v = s.degree_v;
  g.domain_u = nurbs::surface_domain_u(s);
  g.domain_v = nurbs::surface_domain_v(s);
  g.host_knots_u = s.knots_u;
  g.host_knots_v = s.knots_v;
  const nurbs::Box box = nurbs::control_box(s);
  g.origin = 0.5 * (box.min + box.max);
  std::vector<float> pw(s.points.size() * 4);
  for (size_t i = 0; i < s.points.size(); ++i) {
    const double w = s.weights.empty() ? 1.0 : s.weights[i];
    const glm::dvec3 local = (s.points[i] - g.origin) * w;
    pw[4 * i + 0] = static_cast<float>(local.x);
    pw[4 * i + 1] = static_cast<float>(local.y);
    pw[4 * i + 2] = static_cast<float>(local.z);
    pw[4 * i + 3] = static_cast<float>(w);
  }
  g.control = gpgpu::upload_array_pow2(pw, gpgpu::Format::RGBA32F, max_texture_size, 0.0f).texture;
  g.knots_u = normalised_knots(s.knots_u, g.domain_u, max_texture_size);
  g.knots_v = normalised_knots(s.knots_v, g.domain_v, max_texture_size);
  return g;
}

int tile_side(const gpgpu::ContextInfo& info, const TileLimits& limits) {
  int side = info.max_texture_size;
  if (limits.max_side > 0) side = std::min(side, limits.max_side);
  const auto by_bytes = static_cast<int>(std::sqrt(double(limits.max_bytes) / 32.0));
  return std::max(2, std::min(side, by_bytes));
}

void evaluate_surface_tiles(gpgpu::Gpu& gpu, const GpuSurface& s, const nurbs::ParamGrid& params, EvalMethod method,
                            const TileLimits& limits, const std::function<void(GridTile&&)>& visit) {
  if (params.u.size() < 2 || params.v.size() < 2)
    throw std::invalid_argument("evaluate_surface: a grid needs at least 2 x 2 samples");
  const int side = tile_side(gpu.info(), limits);
  const int W = static_cast<int>(params.u.size()), H = static_cast<int>(params.v.size());
  for (int j0 : tile_starts(H, side)) {
    for (int i0 : tile_starts(W, side)) {
      GridTile t;
      t.i0 = i0;
      t.j0 = j0;
      const int w = std::min(side, W - i0), h = std::min(side, H - j0);
      t.points = gpgpu::Texture(w, h, gpgpu::Format::RGBA32F);
      t.normals = gpgpu::Texture(w, h, gpgpu::Format::RGBA32F);
      evaluate_tile(gpu, s, params, t, method);
      gpu.dump("surface_points", t.points);
      gpu.dump("surface_normals", t.normals);
      visit(std::move(t));
    }
  }
}

SurfaceGrid evaluate_surface(gpgpu::Gpu& gpu, const GpuSurface& s, const nurbs::ParamGrid& params, EvalMethod method,
                             const TileLimits& limits) {
  SurfaceGrid grid;
  grid.params = params;
  const int side = tile_side(gpu.info(), limits);
  grid.tiles_u = static_cast<int>(tile_starts(static_cast<int>(params.u.size()), side).size());
  grid.tiles_v = static_cast<int>(tile_starts(static_cast<int>(params.v.size()), side).size());
  evaluate_surface_tiles(gpu, s, params, method, limits, [&](GridTile&& t) { grid.tiles.push_back(std::move(t)); });
  return grid;
}

SurfaceGrid evaluate_surface(gpgpu::Gpu& gpu, const GpuSurface& s, int n, int m, EvalMethod method,
                             const TileLimits& limits) {
  return evaluate_surface(gpu, s, nurbs::uniform_param_grid(s.domain_u, s.domain_v, n, m), method, limits);
}

std::vector<float> SurfaceGrid::read_points() const { return read_all(*this, false); }
std::vector<float> SurfaceGrid::read_normals() const { return read_all(*this, true); }

SurfaceGridCpu evaluate_surface_cpu(const nurbs::Surface& s, const nurbs::ParamGrid& params) {
  SurfaceGridCpu g;
  g.params = params;
  g.points.reserve(size_t(params.samples()));
  g.normals.reserve(g.points.capacity());
  for (double v : params.v) {
    for (double u : params.u) {
      g.points.push_back(nurbs::surface_point(s, u, v));
      g.normals.push_back(nurbs::surface_normal(s, u, v));
    }
  }
  return g;
}

SurfaceGridCpu evaluate_surface_cpu(const nurbs::Surface& s, int n, int m) {
  return evaluate_surface_cpu(s,
                              nurbs::uniform_param_grid(nurbs::surface_domain_u(s), nurbs::surface_domain_v(s), n, m));
}

}  // namespace queries
