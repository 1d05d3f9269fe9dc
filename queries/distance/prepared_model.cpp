#include "queries/distance/prepared_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>

#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/distance/trim_texture.h"

namespace queries {

double float_budget(const nurbs::Surface& s) {
  const nurbs::Box box = nurbs::control_box(s);
  const double magnitude = std::max(glm::length(box.min), glm::length(box.max));
  return 1e-6 * box.diagonal() + 4.0 * 0x1.0p-24 * magnitude;
}

std::optional<FaceCell> PreparedModel::cell_at(size_t a, int x, int y) const {
  for (const AtlasSlot& sl : atlases[a].plan.slots)
    if (x >= sl.x && y >= sl.y && x < sl.x + sl.width - 1 && y < sl.y + sl.height - 1)
      return FaceCell{sl.face, x - sl.x, y - sl.y};
  return std::nullopt;
}

std::vector<uint8_t> crossed_cells(const nurbs::TrimPolygons& trim, const nurbs::ParamGrid& g) {
  const int nu = g.cells_u(), nv = g.cells_v();
  std::vector<uint8_t> out(size_t(nu) * size_t(nv), 0);
  auto cell_of = [](const std::vector<double>& t, double x) {  // the cell holding x, clamped
    const auto it = std::upper_bound(t.begin(), t.end(), x);
    return std::clamp(int(it - t.begin()) - 1, 0, int(t.size()) - 2);
  };
  for (const auto& loop : trim.loops)
    for (size_t e = 0; e < loop.size(); ++e) {
      glm::dvec2 a = loop[e], b = loop[(e + 1) % loop.size()];
      if (a.x > b.x) std::swap(a, b);
      for (int i = cell_of(g.u, a.x), last = cell_of(g.u, b.x); i <= last; ++i) {
        // The part of the edge over column i, then the rows it spans there.
        const double x0 = std::max(a.x, g.u[size_t(i)]), x1 = std::min(b.x, g.u[size_t(i) + 1]);
        double y0 = a.y, y1 = b.y;
        if (b.x > a.x) {
          y0 = a.y + (b.y - a.y) * ((std::min(x0, b.x) - a.x) / (b.x - a.x));
          y1 = a.y + (b.y - a.y) * ((std::max(x1, a.x) - a.x) / (b.x - a.x));
        }
        if (y0 > y1) std::swap(y0, y1);
        for (int j = cell_of(g.v, y0), top = cell_of(g.v, y1); j <= top; ++j)
          out[size_t(j) * size_t(nu) + size_t(i)] = 1;
      }
    }
  return out;
}

double coarse_tolerance(const std::vector<nurbs::TrimmedSurface>& faces, double tolerance) {
  if (faces.empty()) return tolerance;
  nurbs::Box all = nurbs::control_box(faces.front().surface);
  for (const nurbs::TrimmedSurface& f : faces) {
    const nurbs::Box b = nurbs::control_box(f.surface);
    all.min = glm::min(all.min, b.min);
    all.max = glm::max(all.max, b.max);
  }
  return std::max(tolerance, 5e-4 * all.diagonal());
}

PreparedModel prepare_geometry(std::vector<nurbs::TrimmedSurface> faces, double tolerance, long long max_samples,
                               Search search, double coarse) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  PreparedModel m;
  m.tolerance = tolerance;
  m.search = search;
  m.grid_tolerance = search != Search::CoarseToFine ? tolerance
                     : coarse > 0.0                  ? std::max(tolerance, coarse)
                                                     : coarse_tolerance(faces, tolerance);
  m.faces = std::move(faces);
  glm::dvec3 lo(kInf), hi(-kInf);
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const nurbs::Surface& s = m.faces[f].surface;
    const nurbs::Box box = nurbs::control_box(s);
    lo = glm::min(lo, box.min);
    hi = glm::max(hi, box.max);
    const auto t0 = std::chrono::steady_clock::now();
    // The coarse-to-fine search bounds each polynomial Bézier patch once (no adaptive refinement:
    // about 10x cheaper on the paper's surfaces, whose bound it does not change); its refinement
    // adapts to the K_e of each cell anyway. Rational patches keep the adaptive bound (the
    // quotient rule's bound is far looser on one piece).
    m.bounds.push_back(nurbs::filip_bound(s, search == Search::CoarseToFine && !s.rational() ? 1 : 0));
    const auto t1 = std::chrono::steady_clock::now();
    m.grids.push_back(nurbs::certified_grid(m.bounds.back(), m.grid_tolerance, {max_samples}));
    if (!m.grids.back().meets_tolerance) throw GridLimitError(fmt::format("face {}: {}", f, m.grids.back().reason));
    m.trims.push_back(m.faces[f].loops.empty()
                          ? nurbs::TrimPolygons{}
                          : nurbs::flatten_trim(m.faces[f], nurbs::query_flatten_tolerance(s)));
    const auto t2 = std::chrono::steady_clock::now();
    m.bounds_seconds += std::chrono::duration<double>(t1 - t0).count();
    m.grids_seconds += std::chrono::duration<double>(t2 - t1).count();
  }
  m.centre = 0.5 * (lo + hi);
  return m;
}

PreparedModel prepare_model(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> faces, double tolerance,
                            long long max_samples, Search search, int atlas_side) {
  PreparedModel m = prepare_geometry(std::move(faces), tolerance, max_samples, search);
  prepare_atlases(gpu, m, atlas_side);
  return m;
}

void prepare_atlases(gpgpu::Gpu& gpu, PreparedModel& m, int atlas_side) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<nurbs::ParamGrid> params;
  std::vector<std::pair<int, int>> sizes;
  std::vector<double> flatten;
  for (const nurbs::CertifiedGrid& cg : m.grids) {
    params.push_back(cg.grid);
    sizes.emplace_back(int(cg.grid.u.size()), int(cg.grid.v.size()));
    flatten.push_back(trim_flatten_tolerance(cg.grid));
  }
  const int side = std::min(gpu.info().max_texture_size, std::max(atlas_side, 2));
  std::vector<int> unpacked;
  for (const AtlasPlan& plan : plan_atlases(sizes, side, static_cast<long long>(side) * side, unpacked)) {
    m.atlases.push_back(evaluate_atlas(gpu, plan, m.faces, params, flatten));
    std::vector<float> grow;  // (growth, float budget) per slot
    for (const AtlasSlot& sl : plan.slots) {
      const auto f = size_t(sl.face);
      const double budget = float_budget(m.faces[f].surface);
      grow.insert(grow.end(), {float(m.grids[f].k_e + budget), float(budget)});
    }
    if (grow.size() / 2 > size_t(gpu.info().max_texture_size))
      throw std::length_error("prepare_model: more faces in one atlas than the texture size allows");
    m.grow.emplace_back(int(grow.size() / 2), 1, gpgpu::Format::RG32F);
    m.grow.back().upload(grow);
    std::vector<uint8_t> crossed(size_t(plan.width) * size_t(plan.height), 0);
    for (const AtlasSlot& sl : plan.slots) {
      const auto f = size_t(sl.face);
      if (m.faces[f].loops.empty()) continue;
      const nurbs::ParamGrid& g = m.grids[f].grid;
      const std::vector<uint8_t> c = crossed_cells(m.trims[f], g);
      for (int j = 0; j < g.cells_v(); ++j)
        for (int i = 0; i < g.cells_u(); ++i)
          crossed[size_t(sl.y + j) * size_t(plan.width) + size_t(sl.x + i)] =
              c[size_t(j) * size_t(g.cells_u()) + size_t(i)] ? 255 : 0;  // R8 reads 1.0
    }
    m.crossed.emplace_back(plan.width, plan.height, gpgpu::Format::R8);
    m.crossed.back().upload(std::span<const uint8_t>(crossed));
  }
  gpu.finish();
  m.atlas_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!unpacked.empty())
    throw GridLimitError(fmt::format("face {}: its grid is larger than an atlas of {}^2; use a larger tolerance",
                                     unpacked.front(), side));
}

PreparedPair prepare_pair(gpgpu::Gpu& gpu, std::vector<nurbs::TrimmedSurface> a, std::vector<nurbs::TrimmedSurface> b,
                          double tolerance, Search search, long long max_samples,
                          const std::function<void(const std::function<bool()>& geometry_done)>& meanwhile,
                          double coarse_a, double coarse_b) {
  auto geometry = [&](std::vector<nurbs::TrimmedSurface>& faces, double coarse) {
    return std::async(std::launch::async,
                      [&faces, &tolerance, &max_samples, &search, coarse] {
                        return prepare_geometry(std::move(faces), tolerance, max_samples, search, coarse);
                      });
  };
  std::future<PreparedModel> geometry_a = geometry(a, coarse_a), geometry_b = geometry(b, coarse_b);
  const auto done = [&] {
    using namespace std::chrono_literals;
    return geometry_a.wait_for(0s) == std::future_status::ready && geometry_b.wait_for(0s) == std::future_status::ready;
  };
  if (meanwhile) meanwhile(done);
  PreparedPair p{geometry_a.get(), geometry_b.get()};
  prepare_atlases(gpu, p.a);
  prepare_atlases(gpu, p.b);
  return p;
}

int atlas_side(const gpgpu::ContextInfo& info) {
  int side = kAtlasSide;
  if (info.memory_bytes > 0) {
    constexpr long long kBytesPerTexel = 64;
    side = 1024;
    while (2LL * side <= info.max_texture_size && 4LL * side * side * kBytesPerTexel <= info.memory_bytes / 8) side *= 2;
  }
  return std::min(side, info.max_texture_size);
}

}  // namespace queries
