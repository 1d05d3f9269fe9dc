#include "queries/surface_grid.h"

#include <fmt/format.h>

#include <algorithm>
#include <glm/common.hpp>
#include <stdexcept>
#include <string>

#include "nurbs/surface_eval.h"

namespace queries {
namespace {

gpgpu::Texture normalised_knots(const std::vector<double>& knots, nurbs::Interval domain) {
  std::vector<float> k(knots.size());
  for (size_t i = 0; i < knots.size(); ++i) k[i] = static_cast<float>((knots[i] - domain.min) / domain.width());
  gpgpu::Texture t(static_cast<int>(k.size()), 1, gpgpu::Format::R32F);
  t.upload(k);
  return t;
}

}  // namespace

GpuSurface upload_surface(const nurbs::Surface& s, int max_texture_size) {
  const auto max_knots = static_cast<size_t>(max_texture_size);
  if (s.knots_u.size() > max_knots || s.knots_v.size() > max_knots)
    throw std::invalid_argument(fmt::format("surface with {}x{} knots exceeds GL_MAX_TEXTURE_SIZE {}", s.knots_u.size(),
                                            s.knots_v.size(), max_texture_size));
  GpuSurface g;
  g.count_u = s.count_u;
  g.count_v = s.count_v;
  g.degree_u = s.degree_u;
  g.degree_v = s.degree_v;
  glm::dvec3 lo = s.points.front(), hi = s.points.front();
  for (const glm::dvec3& p : s.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  g.origin = 0.5 * (lo + hi);
  std::vector<float> pw(s.points.size() * 4);
  for (size_t i = 0; i < s.points.size(); ++i) {
    const double w = s.weights.empty() ? 1.0 : s.weights[i];
    const glm::dvec3 local = (s.points[i] - g.origin) * w;
    pw[4 * i + 0] = static_cast<float>(local.x);
    pw[4 * i + 1] = static_cast<float>(local.y);
    pw[4 * i + 2] = static_cast<float>(local.z);
    pw[4 * i + 3] = static_cast<float>(w);
  }
  g.control = gpgpu::Texture(s.count_u, s.count_v, gpgpu::Format::RGBA32F);
  g.control.upload(pw);
  g.knots_u = normalised_knots(s.knots_u, nurbs::surface_domain_u(s));
  g.knots_v = normalised_knots(s.knots_v, nurbs::surface_domain_v(s));
  return g;
}

namespace {

/// Pass 1 of EvalMethod::Tabulated for one direction: samples x (degree + 1) basis table.
gpgpu::PooledTexture basis_table(gpgpu::Gpu& gpu, const gpgpu::Texture& knots, int count, int degree, int samples) {
  gpgpu::PooledTexture table = gpu.acquire(samples, degree + 1, gpgpu::Format::RGBA32F);
  gpgpu::Program& p = gpu.program("surface_basis.frag", {{"MAX_DEGREE", std::to_string(degree)}});
  p.set("u_count", count);
  p.set("u_degree", degree);
  p.set("u_samples", samples);
  const gpgpu::Input inputs[] = {{"u_knots", &knots}};
  gpgpu::Texture* outputs[] = {table.get()};
  gpu.run("surface_basis", p, inputs, outputs);
  return table;
}

}  // namespace

SurfaceGrid evaluate_surface(gpgpu::Gpu& gpu, const GpuSurface& s, int n, int m, EvalMethod method) {
  SurfaceGrid grid;
  grid.n = n;
  grid.m = m;
  grid.points = gpgpu::Texture(n + 1, m + 1, gpgpu::Format::RGBA32F);
  grid.normals = gpgpu::Texture(n + 1, m + 1, gpgpu::Format::RGBA32F);
  gpgpu::Texture* outputs[] = {&grid.points, &grid.normals};
  if (method == EvalMethod::PerFragment) {
    gpgpu::Program& p =
        gpu.program("surface_eval.frag", {{"MAX_DEGREE", std::to_string(std::max(s.degree_u, s.degree_v))}});
    p.set("u_count", s.count_u, s.count_v);
    p.set("u_degree", s.degree_u, s.degree_v);
    p.set("u_grid", n + 1, m + 1);
    p.set("u_origin", float(s.origin.x), float(s.origin.y), float(s.origin.z));
    const gpgpu::Input inputs[] = {{"u_knots_u", &s.knots_u}, {"u_knots_v", &s.knots_v}, {"u_ctrl", &s.control}};
    gpu.run("surface_eval", p, inputs, outputs);
  } else {
    gpgpu::PooledTexture bu = basis_table(gpu, s.knots_u, s.count_u, s.degree_u, n + 1);
    gpgpu::PooledTexture bv = basis_table(gpu, s.knots_v, s.count_v, s.degree_v, m + 1);
    gpgpu::Program& p = gpu.program("surface_eval_tabulated.frag");
    p.set("u_degree", s.degree_u, s.degree_v);
    p.set("u_origin", float(s.origin.x), float(s.origin.y), float(s.origin.z));
    const gpgpu::Input inputs[] = {{"u_basis_u", bu.get()}, {"u_basis_v", bv.get()}, {"u_ctrl", &s.control}};
    gpu.run("surface_eval_tabulated", p, inputs, outputs);
  }
  gpu.dump("surface_points", grid.points);
  gpu.dump("surface_normals", grid.normals);
  return grid;
}

SurfaceGridCpu evaluate_surface_cpu(const nurbs::Surface& s, int n, int m) {
  SurfaceGridCpu g;
  g.n = n;
  g.m = m;
  const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
  g.points.reserve(size_t(n + 1) * size_t(m + 1));
  g.normals.reserve(g.points.capacity());
  for (int j = 0; j <= m; ++j) {
    const double v = j == m ? dv.max : dv.min + dv.width() * j / m;
    for (int i = 0; i <= n; ++i) {
      const double u = i == n ? du.max : du.min + du.width() * i / n;
      g.points.push_back(nurbs::surface_point(s, u, v));
      g.normals.push_back(nurbs::surface_normal(s, u, v));
    }
  }
  return g;
}

}  // namespace queries
