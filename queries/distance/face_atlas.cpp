#include "queries/distance/face_atlas.h"

#include <fmt/format.h>

#include <algorithm>
#include <glm/common.hpp>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "gpgpu/array_texture.h"
#include "gpgpu/polygon_fill.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "nurbs/trim_classify.h"
#include "queries/distance/surface_grid.h"
#include "queries/distance/trim_texture.h"
#include "queries/shaders.h"

namespace queries {
namespace {

constexpr double kExactFloatInt = 16777216.0;  // 2^24: indices in float records stay exact below

/// Sutherland-Hodgman clip of a closed polygon to an axis-aligned rectangle. Clipping each polygon
/// to a convex region keeps its winding number at every point inside the region, so the even-odd
/// fill inside one slot is unchanged while nothing leaks into the neighbouring slots.
std::vector<glm::vec2> clip(const std::vector<glm::vec2>& poly, glm::vec2 lo, glm::vec2 hi) {
  std::vector<glm::vec2> out = poly;
  for (int edge = 0; edge < 4 && !out.empty(); ++edge) {
    const int axis = edge % 2;
    const bool keep_above = edge < 2;
    const float bound = keep_above ? lo[axis] : hi[axis];
    auto inside = [&](glm::vec2 p) { return keep_above ? p[axis] >= bound : p[axis] <= bound; };
    std::vector<glm::vec2> in;
    in.swap(out);
    for (size_t k = 0; k < in.size(); ++k) {
      const glm::vec2 a = in[k], b = in[(k + 1) % in.size()];
      if (inside(a)) out.push_back(a);
      if (inside(a) != inside(b)) {
        const float s = (bound - a[axis]) / (b[axis] - a[axis]);
        out.push_back(a + s * (b - a));
      }
    }
  }
  return out;
}

}  // namespace

namespace {

/// Skyline bottom-left packing into a strip `width` wide and at most `height` high: each grid of
/// `order` (in that order) goes where its bottom lies lowest (then leftmost); a grid that does not
/// fit, or would pass `max_samples`, is left in `rest`. The plan's size is what the slots cover.
AtlasPlan skyline(const std::vector<std::pair<int, int>>& sizes, const std::vector<int>& order, int width, int height,
                  long long max_samples, std::vector<int>& rest) {
  struct Segment {
    int x, y, w;
  };
  std::vector<Segment> sky{{0, 0, width}};
  AtlasPlan plan;
  long long used = 0;
  for (int f : order) {
    const auto [w, h] = sizes[size_t(f)];
    int best_y = height, best_i = -1;
    if (w <= width && used + static_cast<long long>(w) * h <= max_samples)
      for (size_t i = 0; i < sky.size(); ++i) {
        if (sky[i].x + w > width) break;
        int y = 0;  // the highest segment under [x, x + w)
        for (size_t k = i; k < sky.size() && sky[k].x < sky[i].x + w; ++k) y = std::max(y, sky[k].y);
        if (y + h <= height && y < best_y) best_y = y, best_i = int(i);
      }
    if (best_i < 0) {
      rest.push_back(f);
      continue;
    }
    const int x = sky[size_t(best_i)].x;
    plan.slots.push_back({f, x, best_y, w, h});
    plan.width = std::max(plan.width, x + w);
    plan.height = std::max(plan.height, best_y + h);
    used += static_cast<long long>(w) * h;
    // The skyline: [x, x + w) at best_y + h; the segments it covers cut or dropped.
    std::vector<Segment> next;
    for (const Segment& g : sky) {
      if (g.x + g.w <= x || g.x >= x + w) {
        next.push_back(g);
        continue;
      }
      if (g.x < x) next.push_back({g.x, g.y, x - g.x});
      if (g.x + g.w > x + w) next.push_back({x + w, g.y, g.x + g.w - (x + w)});
    }
    next.push_back({x, best_y + h, w});
    std::sort(next.begin(), next.end(), [](const Segment& a, const Segment& b) { return a.x < b.x; });
    sky.clear();
    for (const Segment& g : next)
      if (!sky.empty() && sky.back().y == g.y)
        sky.back().w += g.w;
      else
        sky.push_back(g);
  }
  return plan;
}

long long pow2_at_least(int n) {
  long long p = 1;
  while (p < n) p *= 2;
  return p;
}

}  // namespace

std::vector<AtlasPlan> plan_atlases(const std::vector<std::pair<int, int>>& grid_sizes, int side, long long max_samples,
                                    std::vector<int>& unpacked, int align) {
  std::vector<int> order;
  for (int f = 0; f < int(grid_sizes.size()); ++f) {
    if (grid_sizes[size_t(f)].first > side || grid_sizes[size_t(f)].second > side)
      unpacked.push_back(f);
    else
      order.push_back(f);
  }
  // Packed padded to multiples of `align` (so every position is one too), slots of the grids' sizes.
  align = std::max(align, 1);
  std::vector<std::pair<int, int>> sizes = grid_sizes;
  for (auto& [w, h] : sizes)
    w = std::min(side, (w + align - 1) / align * align), h = std::min(side, (h + align - 1) / align * align);
  // Tallest first, then widest.
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return sizes[size_t(a)].second != sizes[size_t(b)].second ? sizes[size_t(a)].second > sizes[size_t(b)].second
                                                              : sizes[size_t(a)].first > sizes[size_t(b)].first;
  });
  std::vector<AtlasPlan> plans;
  while (!order.empty()) {
    // Strip widths from the widest grid's to the side (each power of two between): the one whose
    // plan holds every grid left in the fewest texels once padded to powers of two (the point
    // pyramid's level 0), then in the fewest texels; when none holds them all, the side's.
    int widest = 1;
    for (int f : order) widest = std::max(widest, sizes[size_t(f)].first);
    std::vector<int> widths{widest};
    for (int w = 1; w < side; w *= 2)
      if (w > widest) widths.push_back(w);
    widths.push_back(side);
    AtlasPlan best;
    std::vector<int> best_rest;
    bool found = false;
    for (int w : widths) {
      std::vector<int> rest;
      AtlasPlan plan = skyline(sizes, order, w, side, max_samples, rest);
      if (!rest.empty()) continue;
      const auto key = [](const AtlasPlan& p) {
        return std::pair{pow2_at_least(p.width) * pow2_at_least(p.height), static_cast<long long>(p.width) * p.height};
      };
      if (!found || key(plan) < key(best)) best = std::move(plan), best_rest.clear(), found = true;
    }
    if (!found) best = skyline(sizes, order, side, side, max_samples, best_rest);
    if (best.slots.empty()) throw std::logic_error("plan_atlases: a grid that fits packs into no atlas");
    for (AtlasSlot& sl : best.slots) std::tie(sl.width, sl.height) = grid_sizes[size_t(sl.face)];
    plans.push_back(std::move(best));
    order = std::move(best_rest);
  }
  return plans;
}

FaceAtlas evaluate_atlas(gpgpu::Gpu& gpu, const AtlasPlan& plan, const std::vector<nurbs::TrimmedSurface>& faces,
                         const std::vector<nurbs::ParamGrid>& grids, const std::vector<double>& flatten_tolerance) {
  const int max_size = gpu.info().max_texture_size;
  std::vector<float> slot_of(size_t(plan.width) * size_t(plan.height), -1.0f), records, basis, ctrl;
  for (size_t k = 0; k < plan.slots.size(); ++k) {
    const AtlasSlot& sl = plan.slots[k];
    const nurbs::Surface& s = faces[size_t(sl.face)].surface;
    const nurbs::ParamGrid& g = grids[size_t(sl.face)];
    for (int j = 0; j < sl.height; ++j)
      std::fill_n(slot_of.begin() + ptrdiff_t(size_t(sl.y + j) * size_t(plan.width) + size_t(sl.x)), sl.width,
                  float(k));
    const nurbs::Interval du = nurbs::surface_domain_u(s), dv = nurbs::surface_domain_v(s);
    const size_t base_u = basis.size() / 4;
    const auto bu = tabulate_basis(s.knots_u, s.degree_u, s.count_u, g.u, 0, sl.width, du);
    basis.insert(basis.end(), bu.begin(), bu.end());
    const size_t base_v = basis.size() / 4;
    const auto bv = tabulate_basis(s.knots_v, s.degree_v, s.count_v, g.v, 0, sl.height, dv);
    basis.insert(basis.end(), bv.begin(), bv.end());
    const nurbs::Box box = nurbs::control_box(s);
    const glm::dvec3 origin = 0.5 * (box.min + box.max);
    const size_t ctrl_base = ctrl.size() / 4;
    for (size_t i = 0; i < s.points.size(); ++i) {
      const double w = s.weights.empty() ? 1.0 : s.weights[i];
      const glm::dvec3 local = (s.points[i] - origin) * w;
      ctrl.insert(ctrl.end(), {float(local.x), float(local.y), float(local.z), float(w)});
    }
    if (double(basis.size() / 4) >= kExactFloatInt || double(ctrl.size() / 4) >= kExactFloatInt)
      throw std::length_error("evaluate_atlas: a batch exceeds 2^24 basis values or control points");
    records.insert(records.end(),
                   {float(sl.x), float(sl.y), float(base_u), float(base_v),  //
                    float(ctrl_base), float(s.count_u), float(s.degree_u), float(s.degree_v), float(origin.x),
                    float(origin.y), float(origin.z), float(sl.width), float(sl.height), 0.0f, 0.0f, 0.0f});
  }
  FaceAtlas a;
  a.plan = plan;
  a.slot_of = gpgpu::Texture(plan.width, plan.height, gpgpu::Format::R32F);
  a.slot_of.upload(slot_of);
  const gpgpu::Texture& slot_tex = a.slot_of;
  const auto rec_tex = gpgpu::upload_array_pow2(records, gpgpu::Format::RGBA32F, max_size, 0.0f);
  const auto basis_tex = gpgpu::upload_array_pow2(basis, gpgpu::Format::RGBA32F, max_size, 0.0f);
  const auto ctrl_tex = gpgpu::upload_array_pow2(ctrl, gpgpu::Format::RGBA32F, max_size, 0.0f);
  a.points = gpgpu::Texture(plan.width, plan.height, gpgpu::Format::RGBA32F);
  gpgpu::Program& p = atlas_program(gpu);
  const gpgpu::Input inputs[] = {{"u_slot_of", &slot_tex},
                                 {"u_slots", &rec_tex.texture},
                                 {"u_basis", &basis_tex.texture},
                                 {"u_ctrl", &ctrl_tex.texture}};
  gpgpu::Texture* outputs[] = {&a.points};
  gpu.run("surface_eval_atlas", p, inputs, outputs);
  gpu.dump("atlas_surface_points", a.points);

  a.mask = gpgpu::Texture(plan.width, plan.height, gpgpu::Format::R8);
  if (std::none_of(plan.slots.begin(), plan.slots.end(),
                   [&](const AtlasSlot& sl) { return !faces[size_t(sl.face)].loops.empty(); })) {
    // No face has trim loops: every sample of a slot is material, and the mask is the slots'
    // rectangles, uploaded (the fill below gives the same texels in a pass of its own).
    std::vector<uint8_t> mask(size_t(plan.width) * size_t(plan.height), 0);
    for (const AtlasSlot& sl : plan.slots)
      for (int j = sl.y; j < sl.y + sl.height; ++j)
        std::fill_n(mask.begin() + std::ptrdiff_t(size_t(j) * size_t(plan.width) + size_t(sl.x)), sl.width,
                    uint8_t(255));
    a.mask.upload(std::span<const uint8_t>(mask));
    gpu.dump("atlas_trim_mask", a.mask);
    return a;
  }
  // Trim masks: every slot's loops (or its whole rectangle) in atlas coordinates, clipped to it.
  std::vector<std::vector<glm::vec2>> polygons;
  for (const AtlasSlot& sl : plan.slots) {
    const glm::vec2 lo(float(sl.x), float(sl.y)), hi(float(sl.x + sl.width), float(sl.y + sl.height));
    for (auto& poly :
         trim_window_polygons(faces[size_t(sl.face)], grids[size_t(sl.face)], flatten_tolerance[size_t(sl.face)])) {
      for (glm::vec2& v : poly) v += lo;
      if (auto c = clip(poly, lo, hi); c.size() >= 3) polygons.push_back(std::move(c));
    }
  }
  gpgpu::fill_polygons_even_odd(gpu, polygons, a.mask);
  gpu.dump("atlas_trim_mask", a.mask);
  return a;
}

gpgpu::Program& atlas_program(gpgpu::Gpu& gpu) { return queries::program(gpu, "surface_eval_atlas.frag"); }

}  // namespace queries
