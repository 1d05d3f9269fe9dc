#pragma once
/// \file compact.h
/// Non-uniform stream reduction of Krishnamurthy et al. §1.1 (their ref. [6]), done in fragment
/// passes as a HistoPyramid: count levels built in log4 passes along rows, then along the column
/// (glsl/gpgpu/histopyramid_build.frag), one read-back of the total, then one gather pass in which output
/// element k descends the pyramid to its source texel (glsl/gpgpu/histopyramid_gather.frag).
/// Reducing rows before columns (instead of 2x2 blocks) keeps the output in row-major input order.
/// Beyond that, each level may count 16 texels instead of 4 (`fanout`): half the build passes
/// (llvmpipe pays 0.1-0.3 ms a pass, whatever its size) for up to 4x the reads per gather step.
#include <cstdint>
#include <vector>

#include "gpgpu/gpu.h"
#include "gpgpu/layout.h"

namespace gpgpu {

struct Compacted {
  int64_t count = 0;  ///< kept elements
  Layout2D layout;    ///< of the outputs below (near-square)
  Texture records;    ///< the kept records, in input order (format of the input records)
  Texture source;     ///< R32UI: row-major index of each kept texel in the input
  int levels = 0;     ///< count-pyramid levels built

  /// Reads the first `count` records (channels(format) floats each) / source indices back.
  [[nodiscard]] std::vector<float> read_records() const;
  [[nodiscard]] std::vector<uint32_t> read_source() const;
};

/// Keeps the texels of `records` where channel 0 of `predicate` (same size) is > 0 (R8 masks: set
/// bytes; NaN is not kept). `records` must be a float format. count = 0 gives 1x1 placeholder outputs.
/// `fanout` (4 or 16) is the texels each pyramid level counts along its axis.
Compacted compact(Gpu& gpu, const Texture& predicate, const Texture& records, int fanout = 4);

/// compact() keeping the texels where channel 0 of `values` (a float texture of the records' size)
/// is <= cut (NaN is not kept): the test made by the pyramid's first level and by the gather, in
/// place of a predicate texture written by a pass of its own (a pass and a program fewer).
Compacted compact_at_most(Gpu& gpu, const Texture& values, float cut, const Texture& records, int fanout = 4);

/// Compiles compact()'s (or with `cut`, compact_at_most()'s) programs for `fanout` ahead of its
/// first call (they are otherwise compiled on first use).
void compile_compact(Gpu& gpu, int fanout, bool cut = false);

}  // namespace gpgpu
