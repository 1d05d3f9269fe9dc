#include "queries/raycast/thickness_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "nurbs/stopwatch.h"
#include "nurbs/system_memory.h"
#include "queries/distance/ball_nearest.h"
#include "queries/distance/point_batch.h"
#include "queries/distance/prepared_model.h"

namespace queries {

namespace {

/// Per face and sample of `samples`, -1 everywhere.
nurbs::ray::SampleThickness empty_map(const nurbs::ray::ThicknessSamples& samples) {
  nurbs::ray::SampleThickness th(samples.faces.size());
  for (size_t f = 0; f < samples.faces.size(); ++f) th[f].assign(samples.faces[f].uv.size(), -1.0);
  return th;
}

}  // namespace

ThicknessMapOptions ThicknessMapOptions::paper() const {
  ThicknessMapOptions o = *this;
  o.caster.method = RayMethod::Bvh;
  o.gpu = true;
  o.caster.bvh_build = BvhBuild::Gpu;
  return o;
}

std::vector<nurbs::PaperSwitch> ThicknessMapOptions::paper_switches() {
  return {{"method", "§3.2"}, {"engine", "§3.2-3.4"}, {"bvh-build", "§3.2"}};
}

BallMap ball_map(gpgpu::Gpu& gpu, const nurbs::Model& model, const nurbs::ray::ThicknessRays& rays,
                 const std::vector<nurbs::ray::Hit>& hits, double size, double tolerance, EngineChoice engine,
                 const std::function<void(long long, long long)>& progress) {
  BallMap out;
  const auto t0 = std::chrono::steady_clock::now();
  out.tolerance = tolerance;
  const PreparedModel prepared = prepare_model(gpu, nurbs::world_faces(model), out.tolerance);
  PointBatch batch(gpu, prepared);
  out.engine = choose_engine(engine, gpu);
  batch.set_engine(out.engine);
  gpu.finish();
  out.prepare_seconds = nurbs::seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  std::vector<glm::dvec3> points, inward;
  std::vector<double> start;
  for (size_t r = 0; r < rays.rays.size(); ++r) {
    points.push_back(rays.rays[r].origin);
    inward.push_back(rays.rays[r].direction);
    start.push_back(hits[r].face >= 0 ? 0.5 * hits[r].t : 0.0);
  }
  const auto total = static_cast<long long>(points.size());
  const nurbs::ray::NearestFn query = ball_nearest(batch);
  const nurbs::ray::NearestFn nearest = [&](const std::vector<glm::dvec3>& centres, const std::vector<double>& within) {
    if (progress) progress(total - static_cast<long long>(centres.size()), total);
    auto answer = query(centres, within);
    const PointBatchStats& st = batch.stats();
    out.walks_cut += st.cut, out.cells_tested += st.cells_tested;
    out.gpu_seconds += st.gpu_seconds, out.cpu_seconds += st.cpu_seconds;
    return answer;
  };
  nurbs::ray::BallOptions o;
  o.tolerance = 1e-6 * size;
  o.max_radius = size;
  out.samples = nurbs::ray::ball_thickness(points, inward, start, nearest, o, &out.figures);
  if (progress) progress(total, total);
  out.seconds = nurbs::seconds_since(t1);
  return out;
}

ThicknessMap thickness_map(const nurbs::LoadedModel& loaded, const ThicknessMapOptions& options, gpgpu::Gpu* gpu) {
  const auto start = std::chrono::steady_clock::now();
  ThicknessMap out;
  out.size = loaded.checked_size();
  check_engine_request(options.caster, options.gpu);
  if ((options.gpu || options.ball) && !gpu)
    throw std::logic_error("thickness_map: the GPU caster and the rolling ball need a GL context");
  RayCaster caster(nurbs::world_faces(loaded.model), options.caster, options.gpu ? gpu : nullptr);
  caster.rays_start_on_surfaces();
  out.doubts = HitDoubts(loaded.report, options.accept_partial, caster.method());
  const nurbs::ray::Scene& scene = caster.scene();
  out.scene_faces = scene.faces.size(), out.scene_patches = scene.patches.size(), out.scene_size = scene.size;
  const auto cast = [&](const std::vector<nurbs::ray::Ray>& rays, double t_min, const std::string& what) {
    auto hits = caster.cast(rays, t_min, [&](long long done, long long total) {
      if (options.progress) options.progress(what, done, total);
    });
    out.peak_memory = nurbs::peak_resident_memory();
    return hits;
  };
  // A spacing finer than that of the most samples allowed is refused before the work.
  nurbs::ray::ThicknessOptions o;
  if (const double finest = nurbs::ray::spacing_for_samples(scene, kMaxThicknessSamples);
      options.spacing > 0 && !(options.spacing >= finest))
    throw nurbs::RequestError(fmt::format("--spacing {:g}: below {:.4g}, the spacing of {} samples (the most --samples "
                                          "allows)",
                                          options.spacing, finest, kMaxThicknessSamples));
  o.spacing = options.spacing > 0 ? options.spacing : nurbs::ray::spacing_for_samples(scene, options.samples);
  out.spacing = o.spacing;
  out.samples = nurbs::ray::thickness_samples(scene, o, [&](const std::vector<nurbs::ray::Ray>& r, double t_min) {
    return cast(r, t_min, "thickness: orientation");
  });
  out.rays = nurbs::ray::thickness_rays(out.samples);
  out.orientation_seconds = caster.figures().cast_seconds;
  out.hits = cast(out.rays.rays, o.start_offset * scene.size, "thickness");
  out.cast_seconds = caster.figures().cast_seconds - out.orientation_seconds;
  out.figures = caster.figures();
  out.hit_residual = hit_residual(scene, loaded.report);

  out.thickness = empty_map(out.samples);
  std::vector<double> values;
  for (size_t r = 0; r < out.hits.size(); ++r) {
    const nurbs::ray::Hit& h = out.hits[r];
    if (h.face < 0) continue;
    const auto [f, k] = out.rays.source[r];
    out.thickness[size_t(f)][size_t(k)] = h.t;
    if (out.hit_count == 0 || h.t < out.lo) out.lo = h.t, out.thinnest = r;
    out.hi = out.hit_count == 0 ? h.t : std::max(out.hi, h.t);
    ++out.hit_count;
    out.below_min_wall += options.min_wall > 0 && h.t < options.min_wall ? 1 : 0;
    values.push_back(h.t);
  }
  out.summary = nurbs::ray::summarize_thickness(std::move(values));
  if (options.ball) {
    out.ball = ball_map(*gpu, loaded.model, out.rays, out.hits, out.size, options.ball_tolerance * out.size,
                        options.ball_engine, [&](long long done, long long total) {
                          if (options.progress) options.progress("thickness: rolling ball", done, total);
                        });
    out.ball_thickness = empty_map(out.samples);
    for (size_t r = 0; r < out.rays.rays.size(); ++r)
      out.ball_thickness[size_t(out.rays.source[r].first)][size_t(out.rays.source[r].second)] =
          out.ball->samples[r].thickness;
  }
  out.seconds = nurbs::seconds_since(start);
  return out;
}

}  // namespace queries
