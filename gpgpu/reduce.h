#pragma once
/// \file reduce.h
/// Standard reductions of Krishnamurthy et al. §1.1: min, max, sum and argmin of a texture in
/// ceil(log2(max(w, h))) passes of 2x2 blocks (glsl/gpgpu/reduce_2x2.frag, glsl/gpgpu/argmin_2x2.frag), any size
/// (1x1, 1xN, Nx1, odd, prime), then one read-back of a single texel.
///
/// NaN policy (same on GPU and CPU twin): min/max/argmin ignore NaN entries; a sum containing NaN
/// is NaN. Neutral elements: +inf (min), -inf (max), 0 (sum); argmin of no valid entry is not found.
/// Sums are pairwise (a 2x2 tree) in float: relative error about log2(n) * 2^-24 of sum |x|.
#include <array>
#include <cstdint>
#include <span>

#include "gpgpu/gpu.h"

namespace gpgpu {

enum class ReduceOp : int { Min = 0, Max = 1, Sum = 2 };
using ReduceOps = std::array<ReduceOp, 4>;

/// Reduces each channel of `src` with its operation. Channels the format lacks read as (0, 0, 0, 1).
/// R8 and float formats only. `block`: texels per pass along each axis, 2 (the paper's log2 passes)
/// or, beyond it, 4 or 8 (block^2 texels a pass: block x block, or a row / column of block^2 while
/// the input is one texel high / wide; std::invalid_argument otherwise). Min and max give
/// the same value for any block; sums are added in another order.
std::array<float, 4> reduce(Gpu& gpu, const Texture& src, ReduceOps ops, int block = 2);

/// The program of reduce() for `block` (compiled on first use; callers may compile it ahead).
Program& reduce_program(Gpu& gpu, int block);

/// Minimum / maximum / sum of channel `channel`.
float reduce_min(Gpu& gpu, const Texture& src, int channel = 0, int block = 2);
float reduce_max(Gpu& gpu, const Texture& src, int channel = 0);
float reduce_sum(Gpu& gpu, const Texture& src, int channel = 0);

struct ArgMin {
  bool found = false;  ///< false when every entry is NaN
  float value = 0.0f;
  int x = -1, y = -1;  ///< texel of the minimum; ties go to the smallest row-major index
  int64_t index = -1;  ///< y * width + x
};

/// Minimum of channel `channel` and where it is.
ArgMin argmin(Gpu& gpu, const Texture& src, int channel = 0);

// ---- CPU twins (double precision accumulation), the test oracle -------------------------------

/// `texels` holds width*height texels of `n_channels` floats, row-major.
std::array<double, 4> reduce_cpu(std::span<const float> texels, int n_channels, ReduceOps ops);
ArgMin argmin_cpu(std::span<const float> texels, int width, int n_channels, int channel);

}  // namespace gpgpu
