#include "queries/raycast/raycast_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "gpgpu/layout.h"
#include "nurbs/parallel.h"
#include "nurbs/stopwatch.h"
#include "nurbs/trim_classify.h"
#include "queries/raycast/bvh_gpu.h"
#include "queries/shaders.h"

namespace queries {
namespace {

using nurbs::ray::Hit;
using nurbs::ray::Ray;
using nurbs::ray::Scene;

/// An RGBA32F table of `texels` elements in a power-of-two-wide layout (glsl/gpgpu/lib_layout.glsl
/// pow2_texel), at least 1 x 1; `data` holds 4 floats per element and is padded here.
gpgpu::Texture upload_table(std::vector<float> data, int max_size) {
  const gpgpu::Layout2D l = gpgpu::layout_pow2(std::max<int64_t>(1, int64_t(data.size() / 4)), max_size);
  data.resize(size_t(l.capacity()) * 4, 0.0f);
  gpgpu::Texture t(l.width, l.height, gpgpu::Format::RGBA32F);
  t.upload(data);
  return t;
}

size_t bytes_of(const gpgpu::Texture& t) { return size_t(t.texels()) * 16; }

void push4(std::vector<float>& v, double x, double y, double z, double w) {
  v.insert(v.end(), {float(x), float(y), float(z), float(w)});
}

}  // namespace

GpuRaycaster::GpuRaycaster(gpgpu::Gpu& gpu, const Scene& scene, BvhBuild build) : gpu_(gpu), scene_(scene) {
  if (scene.options.trim != nurbs::ray::SceneOptions::Trim::Cubics)
    throw std::invalid_argument("GpuRaycaster: the scene must be built with SceneOptions::Trim::Cubics (§3.4)");
  const int max_size = gpu.info().max_texture_size;
  // Coordinates relative to the centre of the control points' box: float keeps digits of the
  // scene's size, not of its position.
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const auto& p : scene.patches) lo = glm::min(lo, p.box_min), hi = glm::max(hi, p.box_max);
  centre_ = scene.patches.empty() ? glm::dvec3(0.0) : 0.5 * (lo + hi);
  std::vector<float> patches;
  patches.reserve(scene.patches.size() * 64);
  for (const auto& p : scene.patches) {
    const double extra[16] = {
        double(p.face), glm::length(p.box_max - p.box_min), p.range_u.min, p.range_u.max, p.range_v.min, p.range_v.max};
    for (int i = 0; i < 16; ++i) {
      const glm::dvec3 q = p.p[size_t(i)] - centre_;
      radius_ = std::max(radius_, glm::length(q));
      push4(patches, q.x, q.y, q.z, extra[i]);
    }
  }
  patches_ = upload_table(std::move(patches), max_size);
  if (build == BvhBuild::Gpu && !scene.patches.empty()) {
    build_gpu_bvh();
  } else {
    upload_bvh();
  }
  std::vector<float> cubics, faces;
  for (const auto& tc : scene.cubics) {
    const int first = int(cubics.size() / 12);
    for (const auto& c : tc.cubics) {
      push4(cubics, c.p[0].x, c.p[0].y, c.p[1].x, c.p[1].y);
      push4(cubics, c.p[2].x, c.p[2].y, c.p[3].x, c.p[3].y);
      push4(cubics, first + c.next, first + c.prev, 0.0, 0.0);
    }
    push4(faces, first, double(tc.cubics.size()), 0.0, 0.0);
    push4(faces, tc.domain_u.min, tc.domain_u.max, tc.domain_v.min, tc.domain_v.max);
  }
  constexpr int64_t kExact = int64_t(1) << 24;  // ids are stored as floats
  if (int64_t(cubics.size() / 12) >= kExact || int64_t(scene.bvh.nodes.size()) >= kExact ||
      int64_t(scene.patches.size()) >= kExact)
    throw std::length_error("GpuRaycaster: 2^24 or more patches, nodes or trim cubics (ids stored as floats)");
  cubics_ = upload_table(std::move(cubics), max_size);
  faces_ = upload_table(std::move(faces), max_size);
  stats_ = {.bytes_bvh = bytes_of(nodes_),
            .bytes_patches = bytes_of(patches_),
            .bytes_trims = bytes_of(cubics_) + bytes_of(faces_)};
}

void GpuRaycaster::upload_bvh() {
  std::vector<float> nodes;
  const auto& tree = scene_.bvh.nodes;
  const auto centres = [&](const nurbs::ray::BvhNode& n) {  // near_is_left's vector, in double then rounded
    const auto &l = tree[size_t(n.left)], &r = tree[size_t(n.right)];
    return (l.box_min + l.box_max) - (r.box_min + r.box_max);
  };
  for (size_t i = 0; i < tree.size(); ++i) {
    const nurbs::ray::BvhNode& n = tree[i];
    const glm::dvec3 a = n.box_min - centre_, b = n.box_max - centre_;
    push4(nodes, a.x, a.y, a.z, n.parent);
    push4(nodes, b.x, b.y, b.z, n.left);
    if (n.leaf()) {
      push4(nodes, n.first, n.last, 0.0, -1.0);
    } else {
      const glm::dvec3 c = centres(n);
      push4(nodes, c.x, c.y, c.z, n.right);
    }
    if (n.parent < 0) {
      push4(nodes, 0.0, 0.0, 0.0, 0.0);
    } else {
      const nurbs::ray::BvhNode& p = tree[size_t(n.parent)];
      const glm::dvec3 c = centres(p);
      const bool left = p.left == int(i);
      push4(nodes, c.x, c.y, c.z, left ? p.right : -1 - p.left);
    }
  }
  nodes_ = upload_table(std::move(nodes), gpu_.info().max_texture_size);
}

void GpuRaycaster::build_gpu_bvh() {
  const auto t0 = std::chrono::steady_clock::now();
  // The leaf boxes of build_scene (patch boxes padded by twice the tolerance), as the node table
  // holds them: relative to the centre, rounded to float.
  const glm::dvec3 pad(2.0 * scene_.options.tolerance * scene_.size);
  std::vector<glm::vec3> lo, hi;
  for (const auto& p : scene_.patches) {
    lo.emplace_back(p.box_min - pad - centre_);
    hi.emplace_back(p.box_max + pad - centre_);
  }
  GpuBvh g = build_bvh_gpu(gpu_, lo, hi);
  patches_ = gather_leaves(gpu_, g, patches_, 4);  // 16 texels per patch
  nodes_ = std::move(g.nodes);
  leaf_patch_ = read_order(g);
  build_stats_ = {g.passes + 1, nurbs::seconds_since(t0)};
}

double GpuRaycaster::float_floor(const glm::dvec3& origin) const {
  return kUlps * 0x1.0p-24 * (glm::length(origin - centre_) + radius_);
}

std::vector<RawRayHit> GpuRaycaster::pass(std::span<const Ray> rays, double t_min) {
  std::vector<RawRayHit> out(rays.size());
  if (rays.empty() || scene_.patches.empty()) return out;
  // 16 consecutive rays per 4 x 4 tile, tiles row-major (as point_batch.frag's points).
  int width = 4;
  while (width < 1024 && int64_t(width) * width < int64_t(rays.size())) width *= 2;
  const int64_t tiles_per_row = width / 4, tiles = (int64_t(rays.size()) + 15) / 16;
  const int height = int(4 * ((tiles + tiles_per_row - 1) / tiles_per_row));
  const auto texel_of = [&](size_t i) {
    const int64_t tile = int64_t(i >> 4), t = int64_t(i & 15);
    return size_t((4 * (tile / tiles_per_row) + (t >> 2)) * width + 4 * (tile % tiles_per_row) + (t & 3));
  };
  std::vector<float> o(size_t(width) * size_t(height) * 4, 0.0f), d(o.size(), 0.0f);
  for (size_t i = 0; i < rays.size(); ++i) {
    const glm::vec3 a(rays[i].origin - centre_), b(rays[i].direction);
    std::copy_n(&a.x, 3, o.begin() + ptrdiff_t(4 * texel_of(i)));
    std::copy_n(&b.x, 3, d.begin() + ptrdiff_t(4 * texel_of(i)));
  }
  gpgpu::PooledTexture origins = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  gpgpu::PooledTexture directions = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  origins->upload(o);
  directions->upload(d);
  gpgpu::PooledTexture hits = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  gpgpu::PooledTexture counts = gpu_.acquire(width, height, gpgpu::Format::RGBA32F);
  const nurbs::ray::SceneOptions& opt = scene_.options;
  gpgpu::Program& prog = queries::program(gpu_, "raycast.frag", {{"NEWTON_ITERATIONS", std::to_string(opt.patch.iterations)},
                                                       {"TRIM_ITERATIONS", "3"}});  // inside_trim's default
  prog.set("u_count", int(rays.size()));
  prog.set("u_width", width);
  prog.set("u_patches_width", patches_.width());
  prog.set("u_nodes_width", nodes_.width());
  prog.set("u_cubics_width", cubics_.width());
  prog.set("u_faces_width", faces_.width());
  prog.set("u_max_steps", max_steps_ > 0 ? max_steps_ : 4 * int(scene_.bvh.nodes.size()) + 16);
  prog.set("u_t_min", float(t_min + near_guard_));
  prog.set("u_slack", float(4.0 * opt.tolerance * scene_.size));  // cast_ray's visit
  prog.set("u_ulps", float(kUlps));
  prog.set("u_radius", float(radius_));
  // The exact hit lies within the bicubic tolerance of the patch's (a point error, / cos along the
  // surface); twice cast_ray's slack covers it and the float floor.
  prog.set("u_doubt", float(8.0 * opt.tolerance * scene_.size));
  prog.set("u_scale", float(opt.patch.param_scale));
  prog.set("u_residual", float(opt.patch.residual));
  prog.set("u_edge_margin", float(opt.patch.edge_margin));
  prog.set("u_two", 2);
  const gpgpu::Input in[] = {{"u_origins", origins.get()}, {"u_directions", directions.get()},
                             {"u_patches", &patches_},     {"u_nodes", &nodes_},
                             {"u_cubics", &cubics_},       {"u_faces", &faces_}};
  gpgpu::Texture* target[] = {hits.get(), counts.get()};
  gpu_.run("raycast", prog, in, target);
  const std::vector<float> h = hits->read(), c = counts->read();
  for (size_t i = 0; i < rays.size(); ++i) {
    const float* a = &h[4 * texel_of(i)];
    const float* b = &c[4 * texel_of(i)];
    const int flags = int(b[3]);
    const int leaf = int(a[1]);
    const int patch = leaf < 0 || leaf_patch_.empty() ? leaf : leaf_patch_[size_t(leaf)];
    out[i] = {a[0], patch, a[2], a[3], int(b[0]), int(b[1]), int(b[2]), (flags & 1) != 0, (flags & 2) != 0};
  }
  return out;
}

std::vector<RawRayHit> GpuRaycaster::cast_raw(std::span<const Ray> rays, double t_min) {
  stats_ = {.bytes_bvh = bytes_of(nodes_),
            .bytes_patches = bytes_of(patches_),
            .bytes_trims = bytes_of(cubics_) + bytes_of(faces_)};
  stats_.rays = static_cast<long long>(rays.size());
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<RawRayHit> out;
  out.reserve(rays.size());
  for (size_t s = 0; s < rays.size(); s += rays_per_pass_) {
    const auto part = pass(rays.subspan(s, std::min(rays_per_pass_, rays.size() - s)), t_min);
    out.insert(out.end(), part.begin(), part.end());
  }
  gpu_.finish();
  stats_.gpu_seconds = nurbs::seconds_since(t0);
  for (const RawRayHit& r : out) stats_.box_tests += r.box_tests, stats_.patch_tests += r.patch_tests;
  return out;
}

Hit GpuRaycaster::finish(const Ray& ray, const RawRayHit& raw, double t_min, long long& fallbacks) const {
  auto again = [&] {
    ++fallbacks;
    return nurbs::ray::cast_ray(scene_, ray, t_min);
  };
  if (raw.doubt || raw.cut) return again();
  if (raw.patch < 0) return recast_misses_ ? again() : Hit{};
  const nurbs::ray::BicubicPatch& p = scene_.patches[size_t(raw.patch)];
  const glm::dvec2 uv(p.range_u.min + double(raw.s) * (p.range_u.max - p.range_u.min),
                      p.range_v.min + double(raw.t_param) * (p.range_v.max - p.range_v.min));
  // The first of a grazing pair too (Scene::refine_first): an earlier root on this face is nearer
  // than anything the pass put before it.
  const nurbs::ray::ExactHit e =
      scene_.refine_first(p.face, ray, nurbs::ray::ray_planes(ray), uv, t_min, scene_.material_test(p.face));
  if (!e.ok) return again();
  return {e.t, p.face, e.uv, e.point, double(raw.t)};
}

std::vector<Hit> GpuRaycaster::cast(std::span<const Ray> rays, double t_min) {
  const std::vector<RawRayHit> raw = cast_raw(rays, t_min);
  const auto t1 = std::chrono::steady_clock::now();
  // Independent rays: one contiguous share per thread (at least 128 rays each, at most one per
  // hardware thread or set_threads' count), so the result does not depend on the thread count.
  std::vector<Hit> out(rays.size());
  const size_t threads = threads_ > 0 ? std::min(nurbs::share_count(rays.size(), 128), size_t(threads_))
                                      : nurbs::share_count(rays.size(), 128);
  std::vector<long long> fallbacks(threads, 0);
  nurbs::for_shares(rays.size(), threads, [&](size_t t, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) out[i] = finish(rays[i], raw[i], t_min, fallbacks[t]);
  });
  for (long long f : fallbacks) stats_.fallbacks += f;
  stats_.cpu_seconds = nurbs::seconds_since(t1);
  return out;
}

}  // namespace queries
