#include "nurbs/raycast/thickness.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "nurbs/surface_eval.h"

namespace nurbs::ray {
namespace {

constexpr int kProbe = 9;  ///< points per direction of the grid that measures a face

struct FaceExtent {
  double length_u = 0.0, length_v = 0.0;  ///< longest polyline along u (along v) through the probe grid
  double area = 0.0;                      ///< area of the probe cells whose centre is material
};

/// The face's sampled rectangle: the box of its outer trim loops within the domain (the domain
/// when it has none), so a small face trimmed from a large plane is not sampled where it is not.
struct UvBox {
  glm::dvec2 lo{0.0}, hi{0.0};
};
UvBox material_box(const Scene& scene, int face) {
  const TrimmedSurface& f = scene.faces[face];
  const Interval du = surface_domain_u(f.surface), dv = surface_domain_v(f.surface);
  UvBox domain{{du.min, dv.min}, {du.max, dv.max}}, box{glm::dvec2(1e300), glm::dvec2(-1e300)};
  const TrimPolygons& t = scene.trims[face];
  for (size_t l = 0; l < t.loops.size(); ++l)
    if (t.outer[l])
      for (const glm::dvec2& p : t.loops[l]) {
        box.lo = glm::min(box.lo, p);
        box.hi = glm::max(box.hi, p);
      }
  if (!(box.lo.x <= box.hi.x)) return domain;
  box.lo = glm::max(box.lo, domain.lo);
  box.hi = glm::min(box.hi, domain.hi);
  return box.lo.x < box.hi.x && box.lo.y < box.hi.y ? box : domain;
}

glm::dvec2 grid_uv(const UvBox& b, int i, int j, int nu, int nv, double offset) {
  return {b.lo.x + (i + offset) / nu * (b.hi.x - b.lo.x), b.lo.y + (j + offset) / nv * (b.hi.y - b.lo.y)};
}

bool material(const Scene& scene, int face, glm::dvec2 uv) {
  return scene.is_material(face, uv);
}

FaceExtent measure_face(const Scene& scene, int face) {
  const TrimmedSurface& f = scene.faces[face];
  const UvBox box = material_box(scene, face);
  const int n = kProbe - 1;
  std::vector<glm::dvec3> p(kProbe * kProbe);
  for (int j = 0; j < kProbe; ++j)
    for (int i = 0; i < kProbe; ++i) {
      const glm::dvec2 uv = grid_uv(box, i, j, n, n, 0.0);
      p[j * kProbe + i] = surface_derivatives(f.surface, uv.x, uv.y).s;
    }
  FaceExtent e;
  for (int j = 0; j < kProbe; ++j) {
    double lu = 0.0, lv = 0.0;
    for (int i = 0; i + 1 < kProbe; ++i) {
      lu += glm::length(p[j * kProbe + i + 1] - p[j * kProbe + i]);
      lv += glm::length(p[(i + 1) * kProbe + j] - p[i * kProbe + j]);
    }
    e.length_u = std::max(e.length_u, lu);
    e.length_v = std::max(e.length_v, lv);
  }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (!material(scene, face, grid_uv(box, i, j, n, n, 0.5))) continue;
      const glm::dvec3 &a = p[j * kProbe + i], &b = p[j * kProbe + i + 1], &c = p[(j + 1) * kProbe + i],
                       &d = p[(j + 1) * kProbe + i + 1];
      e.area += 0.5 * (glm::length(glm::cross(b - a, d - a)) + glm::length(glm::cross(d - a, c - a)));
    }
  return e;
}

/// Ray parity (header): per face +1 when Su x Sv points into the material.
void orient_faces(const Scene& scene, const ThicknessOptions& options, const CastFn& cast, ThicknessSamples& out) {
  const int nf = static_cast<int>(scene.faces.size());
  struct Probe {
    int face;
    Ray ray;
    int crossings = 0;
    bool live = true;
  };
  std::vector<Probe> probes;
  for (int f = 0; f < nf; ++f) {
    const TrimmedSurface& face = scene.faces[f];
    const UvBox box = material_box(scene, f);
    int found = 0;
    // Material centres of a 5 x 5 grid, taken in a spread order (middle first).
    static constexpr int kOrder[25] = {12, 6,  18, 8,  16, 0, 24, 4, 20, 7,  17, 11, 13,
                                       2,  22, 10, 14, 1,  3, 5,  9, 15, 19, 21, 23};
    for (int k : kOrder) {
      if (found >= options.parity_points) break;
      const glm::dvec2 uv = grid_uv(box, k % 5, k / 5, 5, 5, 0.5);
      if (!material(scene, f, uv)) continue;
      const SurfaceDerivatives d = surface_derivatives(face.surface, uv.x, uv.y);
      const glm::dvec3 n = glm::cross(d.su, d.sv);
      if (!(glm::length(n) > 0.0) || !(glm::length(d.su) > 0.0) || !(glm::length(d.sv) > 0.0)) continue;
      // A small tilt keeps the ray off the symmetry planes where it would graze edges of the model.
      const glm::dvec3 dir =
          glm::normalize(glm::normalize(n) + 0.0131 * glm::normalize(d.su) + 0.0071 * glm::normalize(d.sv));
      probes.push_back({f, Ray{d.s, dir}});
      ++found;
    }
  }
  const double t_min = options.start_offset * scene.size;
  for (int round = 0; round < 64; ++round) {
    std::vector<Ray> rays;
    std::vector<int> index;
    for (size_t k = 0; k < probes.size(); ++k)
      if (probes[k].live) {
        rays.push_back(probes[k].ray);
        index.push_back(static_cast<int>(k));
      }
    if (rays.empty()) break;
    const std::vector<Hit> hits = cast(rays, t_min);
    for (size_t r = 0; r < rays.size(); ++r) {
      Probe& p = probes[index[r]];
      if (hits[r].face < 0) {
        p.live = false;
      } else {
        ++p.crossings;
        p.ray.origin = hits[r].point;
      }
    }
  }
  std::vector<int> odd(nf, 0), even(nf, 0);
  for (const Probe& p : probes) (p.crossings % 2 == 1 ? odd : even)[p.face] += 1;
  out.inward_sign.assign(nf, -1);
  for (int f = 0; f < nf; ++f) {
    out.inward_sign[f] = odd[f] > even[f] ? +1 : -1;
    if (odd[f] + even[f] == 0 || (odd[f] > 0 && even[f] > 0)) ++out.orientation_unsure;
    const int file_sign = scene.faces[f].reversed ? +1 : -1;  // the file's outward is -inward
    if (odd[f] + even[f] > 0 && file_sign != out.inward_sign[f]) ++out.orientation_flips;
  }
}

}  // namespace

long long ThicknessSamples::count() const {
  long long n = 0;
  for (const auto& f : faces) n += std::count(f.material.begin(), f.material.end(), true);
  return n;
}

double spacing_for_samples(const Scene& scene, long long samples) {
  double area = 0.0;
  for (int f = 0; f < static_cast<int>(scene.faces.size()); ++f) area += measure_face(scene, f).area;
  if (!(area > 0.0) || samples <= 0) return scene.size;
  return std::sqrt(area / static_cast<double>(samples));
}

ThicknessSamples thickness_samples(const Scene& scene, const ThicknessOptions& options, const CastFn& cast) {
  ThicknessSamples out;
  orient_faces(scene, options, cast, out);
  for (int f = 0; f < static_cast<int>(scene.faces.size()); ++f) {
    const TrimmedSurface& face = scene.faces[f];
    const FaceExtent e = measure_face(scene, f);
    const UvBox box = material_box(scene, f);
    FaceSamples s;
    s.face = f;
    // Clamped as doubles: a tiny spacing makes the ratio too large for an int (or infinite).
    const auto cells = [&](double length) {
      return static_cast<int>(std::clamp(std::ceil(length / options.spacing), 1.0, double(options.max_grid)));
    };
    s.nu = cells(e.length_u);
    s.nv = cells(e.length_v);
    const size_t n = static_cast<size_t>(s.nu) * static_cast<size_t>(s.nv);
    s.uv.resize(n);
    s.point.resize(n);
    s.inward.resize(n);
    s.material.assign(n, false);
    for (int j = 0; j < s.nv; ++j)
      for (int i = 0; i < s.nu; ++i) {
        const size_t k = static_cast<size_t>(j) * s.nu + i;
        s.uv[k] = grid_uv(box, i, j, s.nu, s.nv, 0.5);
        if (!material(scene, f, s.uv[k])) continue;
        const SurfaceDerivatives d = surface_derivatives(face.surface, s.uv[k].x, s.uv[k].y);
        const glm::dvec3 normal = surface_normal(face.surface, d, s.uv[k].x, s.uv[k].y);
        if (!(glm::length(normal) > 0.5)) continue;  // degenerate point: no normal, no ray
        s.point[k] = d.s;
        s.inward[k] = double(out.inward_sign[f]) * normal;
        s.material[k] = true;
      }
    out.faces.push_back(std::move(s));
  }
  return out;
}

ThicknessRays thickness_rays(const ThicknessSamples& samples) {
  ThicknessRays out;
  for (size_t f = 0; f < samples.faces.size(); ++f) {
    const FaceSamples& s = samples.faces[f];
    for (size_t k = 0; k < s.uv.size(); ++k) {
      if (!s.material[k]) continue;
      out.rays.push_back(Ray{s.point[k], s.inward[k]});
      out.source.emplace_back(static_cast<int>(f), static_cast<int>(k));
    }
  }
  return out;
}

glm::dvec3 thickness_ramp(double x) {
  x = std::clamp(x, 0.0, 1.0);
  const auto stop = [](int k) { return glm::dvec3(kThicknessRamp[k][0], kThicknessRamp[k][1], kThicknessRamp[k][2]); };
  if (x < 1.0 / 3.0) return glm::mix(stop(0), stop(1), 3.0 * x);
  if (x < 2.0 / 3.0) return glm::mix(stop(1), stop(2), 3.0 * x - 1.0);
  return glm::mix(stop(2), stop(3), 3.0 * x - 2.0);
}

glm::dvec3 thickness_colour(double t, double lo, double hi) {
  if (t < 0) return glm::dvec3(0.5);
  return thickness_ramp(hi > lo ? (t - lo) / (hi - lo) : 0.0);
}

TriangleMesh thickness_mesh(const ThicknessSamples& samples, const SampleThickness& thickness, double lo, double hi,
                            std::vector<double>* vertex_thickness) {
  TriangleMesh m;
  m.values_name = "thickness";
  if (vertex_thickness) vertex_thickness->clear();
  for (size_t f = 0; f < samples.faces.size(); ++f) {
    const FaceSamples& g = samples.faces[f];
    std::vector<int> id(g.uv.size(), -1);
    for (size_t k = 0; k < g.uv.size(); ++k) {
      if (!g.material[k]) continue;
      id[k] = static_cast<int>(m.positions.size());
      m.positions.push_back(g.point[k]);
      m.normals.push_back(-g.inward[k]);
      m.uv.push_back(g.uv[k]);
      m.vertex_face.push_back(g.face);
      m.colors.push_back(thickness_colour(thickness[f][k], lo, hi));
      m.values.push_back(thickness[f][k]);
      if (vertex_thickness) vertex_thickness->push_back(thickness[f][k]);
    }
    const bool flip = samples.inward_sign[size_t(g.face)] > 0;  // Su x Sv points inward: reverse the grid's order
    for (int j = 0; j + 1 < g.nv; ++j)
      for (int i = 0; i + 1 < g.nu; ++i) {
        const size_t k = static_cast<size_t>(j) * static_cast<size_t>(g.nu) + static_cast<size_t>(i);
        const int a = id[k], b = id[k + 1], c = id[k + size_t(g.nu)], d = id[k + size_t(g.nu) + 1];
        if (a < 0 || b < 0 || c < 0 || d < 0) continue;
        m.triangles.push_back(flip ? glm::ivec3(a, d, b) : glm::ivec3(a, b, d));
        m.triangles.push_back(flip ? glm::ivec3(a, c, d) : glm::ivec3(a, d, c));
        m.triangle_face.insert(m.triangle_face.end(), 2, g.face);
      }
  }
  return m;
}

ThicknessSummary summarize_thickness(std::vector<double> values) {
  ThicknessSummary r;
  if (values.empty()) return r;
  std::sort(values.begin(), values.end());
  double sum = 0.0;
  for (double v : values) sum += v;
  r.count = static_cast<long long>(values.size());
  r.min = values.front(), r.max = values.back(), r.median = values[values.size() / 2];
  r.mean = sum / double(values.size());
  return r;
}

}  // namespace nurbs::ray
