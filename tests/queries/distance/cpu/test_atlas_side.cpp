// The atlas side from the context's limits (queries/distance/prepared_model.h, atlas_side): within the
// texture size, an eighth of the GPU's memory at most, kAtlasSide where the memory is not known.
#include <doctest/doctest.h>

#include "queries/distance/prepared_model.h"

TEST_CASE("atlas side: from the GPU's texture size and memory") {
  gpgpu::ContextInfo info;
  info.max_texture_size = 16384;
  CHECK(queries::atlas_side(info) == queries::kAtlasSide);  // llvmpipe: no memory figure
  info.max_texture_size = 2048;
  CHECK(queries::atlas_side(info) == 2048);
  info.max_texture_size = 32768;
  info.memory_bytes = 80LL << 30;  // 8192^2 x 64 bytes = 4 GiB <= 10 GiB; 16384^2 x 64 = 16 GiB is not
  CHECK(queries::atlas_side(info) == 8192);
  info.memory_bytes = 4LL << 30;  // 2048^2 x 64 = 256 MiB <= 512 MiB; 4096^2 x 64 = 1 GiB is not
  CHECK(queries::atlas_side(info) == 2048);
  info.memory_bytes = 256LL << 20;  // never below 1024
  CHECK(queries::atlas_side(info) == 1024);
}
