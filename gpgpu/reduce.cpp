#include "gpgpu/reduce.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace gpgpu {
namespace {

Format reduced_format(Format f) {
  if (is_integer(f)) throw std::invalid_argument("reductions of integer textures are not supported");
  return f == Format::R8 ? Format::R32F : f;
}

/// Runs passes of `program` from `src` until 1x1; returns the 1x1 texel. Block 2: 2x2 texels a pass
/// (the paper's); 4 or 8: block x block, or a row (column) of block^2 texels while the input is one
/// texel high (wide), set in u_block (a 2048 x 1 input: 3 passes of 16 instead of 6 of 4).
std::vector<float> pyramid(Gpu& gpu, const Texture& src, Program& first, Program& rest, Format out_format,
                           const char* name, int block = 2) {
  const Texture* in = &src;
  PooledTexture level;
  Program* prog = &first;
  do {
    int bx = block, by = block;
    if (block > 2 && in->height() == 1) bx = block * block, by = 1;
    if (block > 2 && in->width() == 1) bx = 1, by = block * block;
    const int w = (in->width() + bx - 1) / bx, h = (in->height() + by - 1) / by;
    PooledTexture next = gpu.acquire(w, h, out_format);
    if (block > 2) prog->set("u_block", bx, by);
    prog->set("u_src_size", in->width(), in->height());
    const Input inputs[] = {{"u_src", in}};
    Texture* outputs[] = {next.get()};
    gpu.run(name, *prog, inputs, outputs);
    level = std::move(next);
    in = level.get();
    prog = &rest;
  } while (in->width() > 1 || in->height() > 1);
  return level->read();
}

}  // namespace

Program& reduce_program(Gpu& gpu, int block) {
  if (block != 2 && block != 4 && block != 8) throw std::invalid_argument("reduce: block must be 2, 4 or 8");
  return block == 2 ? gpu.program("reduce_2x2.frag")
                    : gpu.program("reduce_2x2.frag", {{"BLOCK", std::to_string(block)}});
}

std::array<float, 4> reduce(Gpu& gpu, const Texture& src, ReduceOps ops, int block) {
  Program& p = reduce_program(gpu, block);
  const Format out = reduced_format(src.format());
  p.set("u_ops", int(ops[0]), int(ops[1]), int(ops[2]), int(ops[3]));
  const std::vector<float> v = pyramid(gpu, src, p, p, out, block == 2 ? "reduce_2x2" : "reduce_block", block);
  std::array<float, 4> result{0, 0, 0, 1};
  for (size_t c = 0; c < v.size(); ++c) result[c] = v[c];
  return result;
}

float reduce_min(Gpu& gpu, const Texture& src, int channel, int block) {
  return reduce(gpu, src, {ReduceOp::Min, ReduceOp::Min, ReduceOp::Min, ReduceOp::Min}, block)[size_t(channel)];
}
float reduce_max(Gpu& gpu, const Texture& src, int channel) {
  return reduce(gpu, src, {ReduceOp::Max, ReduceOp::Max, ReduceOp::Max, ReduceOp::Max})[size_t(channel)];
}
float reduce_sum(Gpu& gpu, const Texture& src, int channel) {
  return reduce(gpu, src, {ReduceOp::Sum, ReduceOp::Sum, ReduceOp::Sum, ReduceOp::Sum})[size_t(channel)];
}

ArgMin argmin(Gpu& gpu, const Texture& src, int channel) {
  if (channel < 0 || channel >= channels(src.format())) throw std::invalid_argument("argmin channel out of range");
  reduced_format(src.format());
  Program& first = gpu.program("argmin_2x2.frag", {{"FIRST_PASS", "1"}});
  Program& rest = gpu.program("argmin_2x2.frag", {{"FIRST_PASS", "0"}});
  first.set("u_channel", channel);
  const std::vector<float> v = pyramid(gpu, src, first, rest, Format::RGBA32F, "argmin_2x2");
  ArgMin r;
  if (v[1] < 0.0f) return r;
  r.found = true;
  r.value = v[0];
  r.x = static_cast<int>(v[1]);
  r.y = static_cast<int>(v[2]);
  r.index = int64_t(r.y) * src.width() + r.x;
  return r;
}

std::array<double, 4> reduce_cpu(std::span<const float> texels, int n_channels, ReduceOps ops) {
  std::array<double, 4> acc{};
  for (int c = 0; c < 4; ++c)
    acc[size_t(c)] = ops[size_t(c)] == ReduceOp::Min   ? std::numeric_limits<double>::infinity()
                     : ops[size_t(c)] == ReduceOp::Max ? -std::numeric_limits<double>::infinity()
                                                       : 0.0;
  const size_t n = texels.size() / size_t(n_channels);
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < n_channels; ++c) {
      const double v = texels[i * size_t(n_channels) + size_t(c)];
      double& a = acc[size_t(c)];
      switch (ops[size_t(c)]) {
        case ReduceOp::Sum:
          a += v;
          break;
        case ReduceOp::Min:
          if (!std::isnan(v)) a = std::min(a, v);
          break;
        case ReduceOp::Max:
          if (!std::isnan(v)) a = std::max(a, v);
          break;
      }
    }
  }
  for (int c = n_channels; c < 4; ++c) acc[size_t(c)] = c == 3 ? 1.0 : 0.0;
  return acc;
}

ArgMin argmin_cpu(std::span<const float> texels, int width, int n_channels, int channel) {
  ArgMin r;
  const size_t n = texels.size() / size_t(n_channels);
  for (size_t i = 0; i < n; ++i) {
    const float v = texels[i * size_t(n_channels) + size_t(channel)];
    if (std::isnan(v) || (r.found && !(v < r.value))) continue;
    r.found = true;
    r.value = v;
    r.index = int64_t(i);
  }
  if (r.found) {
    r.x = int(r.index % width);
    r.y = int(r.index / width);
  }
  return r;
}

}  // namespace gpgpu
