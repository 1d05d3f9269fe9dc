#include "queries/raycast/bvh_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "gpgpu/layout.h"
#include "gpgpu/reduce.h"
#include "queries/shaders.h"

namespace queries {
namespace {

using gpgpu::Format;
using gpgpu::Input;
using gpgpu::Texture;

Texture table(int64_t count, int max_size) {
  const gpgpu::Layout2D l = gpgpu::layout_pow2(std::max<int64_t>(count, 1), max_size);
  return Texture(l.width, l.height, Format::RGBA32F);
}

Texture upload_vec3(std::span<const glm::vec3> v, int max_size) {
  Texture t = table(int64_t(v.size()), max_size);
  std::vector<float> data(size_t(t.texels()) * 4, 0.0f);
  for (size_t i = 0; i < v.size(); ++i) std::copy_n(&v[i].x, 3, data.begin() + ptrdiff_t(4 * i));
  t.upload(data);
  return t;
}

/// The Morton frame of step 1: least centroid and 1 / extent per axis, in float.
struct Frame {
  glm::vec3 lo, inv_ext;
};

Frame frame_of(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 ext = glm::max(hi - lo, glm::vec3(1e-30f));
  return {lo, glm::vec3(1.0f) / ext};
}

}  // namespace

std::vector<std::uint32_t> morton_codes_float(std::span<const glm::vec3> box_min, std::span<const glm::vec3> box_max) {
  const size_t n = box_min.size();
  std::vector<glm::vec3> c(n);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (size_t i = 0; i < n; ++i) {
    c[i] = 0.5f * (box_min[i] + box_max[i]);
    lo = glm::min(lo, c[i]);
    hi = glm::max(hi, c[i]);
  }
  const Frame f = frame_of(lo, hi);
  std::vector<std::uint32_t> codes(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 q = glm::clamp(glm::floor((c[i] - f.lo) * f.inv_ext * 1024.0f), 0.0f, 1023.0f);
    codes[i] = nurbs::ray::morton3_cells(std::uint32_t(q.x), std::uint32_t(q.y), std::uint32_t(q.z));
  }
  return codes;
}

nurbs::ray::Bvh bvh_twin(std::span<const glm::vec3> box_min, std::span<const glm::vec3> box_max) {
  const std::vector<glm::dvec3> lo(box_min.begin(), box_min.end()), hi(box_max.begin(), box_max.end());
  return nurbs::ray::build_bvh_codes(morton_codes_float(box_min, box_max), lo, hi);
}

GpuBvh build_bvh_gpu(gpgpu::Gpu& gpu, std::span<const glm::vec3> box_min, std::span<const glm::vec3> box_max) {
  const auto t0 = std::chrono::steady_clock::now();
  const int64_t n = int64_t(box_min.size());
  if (n == 0 || box_max.size() != box_min.size())
    throw std::invalid_argument("build_bvh_gpu: no leaves, or as many box minima as maxima needed");
  if (n >= (int64_t(1) << 24)) throw std::length_error("build_bvh_gpu: 2^24 leaves or more (ids stored as floats)");
  const int max_size = gpu.info().max_texture_size;
  GpuBvh out;
  out.leaves = int(n);
  const int leaves = int(n);
  const Texture in_min = upload_vec3(box_min, max_size), in_max = upload_vec3(box_max, max_size);
  const int in_width = in_min.width();
  // 0. The centroids' box.
  Texture centroids(in_min.width(), in_min.height(), Format::RGBA32F);
  {
    gpgpu::Program& p = queries::program(gpu, "bvh_centroid.frag");
    p.set("u_width", in_width);
    p.set("u_n", leaves);
    const Input in[] = {{"u_box_min", &in_min}, {"u_box_max", &in_max}};
    Texture* target[] = {&centroids};
    gpu.run("bvh centroids", p, in, target);
  }
  using gpgpu::ReduceOp;
  const auto lo4 = gpgpu::reduce(gpu, centroids, {ReduceOp::Min, ReduceOp::Min, ReduceOp::Min, ReduceOp::Min});
  const auto hi4 = gpgpu::reduce(gpu, centroids, {ReduceOp::Max, ReduceOp::Max, ReduceOp::Max, ReduceOp::Max});
  const int reduce_passes =
      2 * std::max(1, int(std::bit_width(unsigned(std::max(in_min.width(), in_min.height()) - 1))));
  const Frame f = frame_of({lo4[0], lo4[1], lo4[2]}, {hi4[0], hi4[1], hi4[2]});
  // 1. Keys.
  const int64_t padded = int64_t(std::bit_ceil(std::uint64_t(n)));
  Texture keys = table(padded, max_size), scratch = table(padded, max_size);
  const int kw = keys.width();
  {
    gpgpu::Program& p = queries::program(gpu, "bvh_morton.frag");
    p.set("u_width", kw);
    p.set("u_n", leaves);
    p.set("u_lo", f.lo.x, f.lo.y, f.lo.z);
    p.set("u_inv_ext", f.inv_ext.x, f.inv_ext.y, f.inv_ext.z);
    const Input in[] = {{"u_box_min", &in_min}, {"u_box_max", &in_max}};
    Texture* target[] = {&keys};
    if (in_width != kw) throw std::logic_error("build_bvh_gpu: box and key layouts differ");
    gpu.run("bvh morton", p, in, target);
  }
  int passes = 2 + reduce_passes;
  // 2. Bitonic sort.
  {
    gpgpu::Program& p = queries::program(gpu, "bvh_sort.frag");
    p.set("u_width", kw);
    for (int64_t k = 2; k <= padded; k *= 2)
      for (int64_t j = k / 2; j >= 1; j /= 2) {
        p.set("u_k", int(k));
        p.set("u_j", int(j));
        const Input in[] = {{"u_src", &keys}};
        Texture* target[] = {&scratch};
        gpu.run("bvh sort", p, in, target);
        std::swap(keys, scratch);
        ++passes;
      }
  }
  // 3. Internal nodes, 4. parents.
  const int64_t node_count = 2 * n - 1;
  Texture internal = table(node_count, max_size), parent = table(node_count, max_size);
  const int nw = internal.width();
  const auto key_uniforms = [&](gpgpu::Program& p) {
    p.set("u_keys_width", kw);
    p.set("u_n", leaves);
  };
  {
    gpgpu::Program& p = queries::program(gpu, "bvh_karras.frag");
    key_uniforms(p);
    p.set("u_width", nw);
    const Input in[] = {{"u_keys", &keys}};
    Texture* target[] = {&internal};
    gpu.run("bvh karras", p, in, target);
    gpgpu::Program& q = queries::program(gpu, "bvh_parent.frag");
    key_uniforms(q);
    q.set("u_width", nw);
    const Input in2[] = {{"u_keys", &keys}, {"u_internal", &internal}};
    Texture* target2[] = {&parent};
    gpu.run("bvh parents", q, in2, target2);
    passes += 2;
  }
  // 5. Boxes: the sparse table level by level, each level's nodes as soon as it exists.
  Texture t_min = table(padded, max_size), t_max = table(padded, max_size);
  Texture s_min = table(padded, max_size), s_max = table(padded, max_size);
  Texture node_min = table(node_count, max_size), node_max = table(node_count, max_size);
  {
    gpgpu::Program& p0 = queries::program(gpu, "bvh_boxes.frag", {{"STAGE", "0"}});
    key_uniforms(p0);
    p0.set("u_src_width", in_width);
    p0.set("u_width", kw);
    const Input in[] = {{"u_keys", &keys}, {"u_min", &in_min}, {"u_max", &in_max}};
    Texture* target[] = {&t_min, &t_max};
    gpu.run("bvh boxes leaves", p0, in, target);
    ++passes;
    gpgpu::Program& p1 = queries::program(gpu, "bvh_boxes.frag", {{"STAGE", "1"}});
    gpgpu::Program& p2 = queries::program(gpu, "bvh_boxes.frag", {{"STAGE", "2"}});
    for (int level = 0; (int64_t(1) << level) <= n; ++level) {
      if (level > 0) {
        key_uniforms(p1);
        p1.set("u_src_width", kw);
        p1.set("u_width", kw);
        p1.set("u_level", level);
        const Input in1[] = {{"u_min", &t_min}, {"u_max", &t_max}};
        Texture* target1[] = {&s_min, &s_max};
        gpu.run("bvh boxes level", p1, in1, target1);
        std::swap(t_min, s_min);
        std::swap(t_max, s_max);
        ++passes;
      }
      key_uniforms(p2);
      p2.set("u_src_width", kw);
      p2.set("u_width", nw);
      p2.set("u_level", level);
      const Input in2[] = {{"u_min", &t_min}, {"u_max", &t_max}, {"u_internal", &internal}};
      Texture* target2[] = {&node_min, &node_max};
      gpu.run("bvh boxes nodes", p2, in2, target2);
      ++passes;
    }
  }
  // 6. The node table.
  out.nodes = table(4 * node_count, max_size);
  {
    gpgpu::Program& p = queries::program(gpu, "bvh_pack.frag");
    p.set("u_nodes_width", nw);
    p.set("u_width", out.nodes.width());
    p.set("u_n", leaves);
    const Input in[] = {{"u_internal", &internal}, {"u_parent", &parent}, {"u_min", &node_min}, {"u_max", &node_max}};
    Texture* target[] = {&out.nodes};
    gpu.run("bvh pack", p, in, target);
    ++passes;
  }
  out.keys = std::move(keys);
  out.passes = passes;
  gpu.finish();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

Texture gather_leaves(gpgpu::Gpu& gpu, const GpuBvh& bvh, const Texture& src, int shift) {
  if ((int64_t(bvh.leaves) << shift) > src.texels())
    throw std::invalid_argument(fmt::format("gather_leaves: a table of {} texels for {} leaves of {} texels",
                                            src.texels(), bvh.leaves, 1 << shift));
  Texture out(src.width(), src.height(), Format::RGBA32F);
  gpgpu::Program& p = queries::program(gpu, "bvh_gather.frag");
  p.set("u_keys_width", bvh.keys.width());
  p.set("u_n", bvh.leaves);
  p.set("u_width", src.width());
  p.set("u_shift", shift);
  const Input in[] = {{"u_keys", &bvh.keys}, {"u_src", &src}};
  Texture* target[] = {&out};
  gpu.run("bvh gather", p, in, target);
  return out;
}

std::vector<int> read_order(const GpuBvh& bvh) {
  const std::vector<float> k = bvh.keys.read();
  std::vector<int> order(size_t(bvh.leaves));
  for (size_t i = 0; i < order.size(); ++i) order[i] = int(k[4 * i + 2]);
  return order;
}

nurbs::ray::Bvh read_bvh(const GpuBvh& g) {
  nurbs::ray::Bvh bvh;
  const int n = g.leaves;
  const std::vector<float> k = g.keys.read(), t = g.nodes.read();
  for (int i = 0; i < n; ++i) {
    bvh.order.push_back(int(k[4 * size_t(i) + 2]));
    bvh.codes.push_back(std::uint32_t(k[4 * size_t(i)]) * 32768u + std::uint32_t(k[4 * size_t(i) + 1]));
  }
  bvh.nodes.resize(size_t(2 * n - 1));
  for (size_t c = 0; c < bvh.nodes.size(); ++c) {
    const float* e = &t[16 * c];
    nurbs::ray::BvhNode& node = bvh.nodes[c];
    node.box_min = {e[0], e[1], e[2]};
    node.parent = int(e[3]);
    node.box_max = {e[4], e[5], e[6]};
    node.left = int(e[7]);
    if (node.left < 0) {
      node.first = int(e[8]);
      node.last = int(e[9]);
    } else {
      node.right = int(e[11]);
    }
  }
  return bvh;
}

}  // namespace queries
