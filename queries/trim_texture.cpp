#include "queries/trim_texture.h"

#include "gpgpu/polygon_fill.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"

namespace queries {

gpgpu::Texture trim_texture(gpgpu::Gpu& gpu, const nurbs::TrimmedSurface& face, int n, int m,
                            double flatten_tolerance) {
  gpgpu::Texture mask(n + 1, m + 1, gpgpu::Format::R8);
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, flatten_tolerance);
  const nurbs::Interval du = trim.domain_u, dv = trim.domain_v;
  // Sample i sits at u0 + (u1 - u0) i / n, i.e. at window x = i + 0.5.
  auto window = [&](glm::dvec2 uv) {
    return glm::vec2(float((uv.x - du.min) / du.width() * n + 0.5), float((uv.y - dv.min) / dv.width() * m + 0.5));
  };
  std::vector<std::vector<glm::vec2>> polygons;
  bool has_outer = false;
  for (size_t k = 0; k < trim.loops.size(); ++k) {
    has_outer = has_outer || trim.outer[k];
    std::vector<glm::vec2> poly;
    poly.reserve(trim.loops[k].size());
    for (const glm::dvec2& p : trim.loops[k]) poly.push_back(window(p));
    polygons.push_back(std::move(poly));
  }
  if (!has_outer) {  // the domain rectangle is the outer boundary (covers every sample)
    const float w = float(n + 1), h = float(m + 1);
    polygons.push_back({{0.f, 0.f}, {w, 0.f}, {w, h}, {0.f, h}});
  }
  gpgpu::fill_polygons_even_odd(gpu, polygons, mask);
  gpu.dump("trim_mask", mask);
  return mask;
}

std::vector<uint8_t> trim_mask_cpu(const nurbs::TrimmedSurface& face, int n, int m, double flatten_tolerance) {
  const nurbs::TrimPolygons trim = nurbs::flatten_trim(face, flatten_tolerance);
  const nurbs::Interval du = nurbs::surface_domain_u(face.surface), dv = nurbs::surface_domain_v(face.surface);
  std::vector<uint8_t> mask;
  mask.reserve(size_t(n + 1) * size_t(m + 1));
  for (int j = 0; j <= m; ++j) {
    const double v = j == m ? dv.max : dv.min + dv.width() * j / m;
    for (int i = 0; i <= n; ++i) {
      const double u = i == n ? du.max : du.min + du.width() * i / n;
      mask.push_back(nurbs::is_material(trim, {u, v}) ? 1 : 0);
    }
  }
  return mask;
}

}  // namespace queries
