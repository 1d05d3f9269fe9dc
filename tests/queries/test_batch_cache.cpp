// The batched preparation's disk cache (queries/batch_cache.h): a state exported, written, read and
// restored answers every point as the batch it came from, bit for bit; a file of another key, a
// truncated or damaged file, and a state of other grids are misses, never errors.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "../gpgpu/gl_fixture.h"
#include "queries/batch_cache.h"
#include "queries/point_batch.h"
#include "tests/queries/point_batch_fixtures.h"

namespace {

std::filesystem::path temp_dir() {
  const auto d = std::filesystem::temp_directory_path() / ("nurbsgl_batch_cache_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("batch cache: a restored batch answers as the batch it was exported from, bit for bit") {
  gpgpu::Gpu& gpu = test::gpu();
  const auto faces = test::spread_faces(5);  // trimmed and untrimmed faces
  const double tol = 2e-3;
  queries::PreparedModel m = queries::prepare_geometry(faces, tol);
  int side = 2;  // the largest grid's side: several atlases travel
  for (const auto& g : m.grids) side = std::max({side, int(g.grid.u.size()), int(g.grid.v.size())});
  queries::prepare_atlases(gpu, m, side);
  REQUIRE(m.atlases.size() > 1);
  queries::PointBatch built(gpu, m);
  const auto points = test::random_points(faces, 400, 91);
  const auto expected = built.query(points);

  const auto dir = temp_dir();
  const auto file = dir / "state.batch";
  const queries::PointBatchState exported = built.export_state();
  REQUIRE(queries::save_batch_state(file, "key one", exported).empty());
  {
    // Written from the live batch's own arrays (what the CLI does, no copy): the same bytes.
    const auto direct = dir / "direct.batch";
    REQUIRE(queries::save_batch_state(direct, "key one", built.state_view()).empty());
    std::ifstream x(file, std::ios::binary), y(direct, std::ios::binary);
    const std::string bx((std::istreambuf_iterator<char>(x)), {}), by((std::istreambuf_iterator<char>(y)), {});
    CHECK(bx.size() > 1000);
    CHECK(bx == by);
    std::filesystem::remove(direct);
  }
  {
    // The per-texel arrays are stored for the slots' texels only: the file holds less than the
    // padded atlases would, and no more than the slots, the pyramid and the trim data.
    long long slot_texels = 0, atlas_texels = 0, other = 0;
    for (const auto& at : exported.atlases) {
      atlas_texels += static_cast<long long>(at.plan.width) * at.plan.height;
      for (const auto& sl : at.plan.slots) slot_texels += static_cast<long long>(sl.width) * sl.height;
      other += static_cast<long long>(4 * (at.trim_head.size() + at.trim_segs.size()));
      for (const auto& level : at.obb) other += static_cast<long long>(4 * level.texels.size() + 4 * 12 * level.texels.size());
    }
    const auto bytes = static_cast<long long>(std::filesystem::file_size(file));
    MESSAGE("cache file " << bytes << " bytes; " << slot_texels << " slot texels of " << atlas_texels);
    REQUIRE(slot_texels < atlas_texels);
    CHECK(bytes <= 32 * slot_texels + other + 4096);
  }
  CHECK_FALSE(queries::load_batch_state(file, "key two").has_value());  // another model or tolerance
  std::optional<queries::PointBatchState> state = queries::load_batch_state(file, "key one");
  REQUIRE(state.has_value());

  queries::PreparedModel restored = queries::prepare_geometry(faces, tol);
  REQUIRE(queries::state_matches(restored, *state));
  CHECK_FALSE(queries::state_matches(queries::prepare_geometry(faces, 2 * tol), *state));  // other grids
  queries::restore_atlases(restored, *state);
  queries::PointBatch again(gpu, restored, std::move(*state));
  const auto got = again.query(points);
  REQUIRE(got.size() == expected.size());
  int differ = 0;
  for (size_t k = 0; k < got.size(); ++k)
    differ += got[k].distance != expected[k].distance || got[k].face != expected[k].face ||
              got[k].point != expected[k].point || got[k].bound != expected[k].bound;
  CHECK(differ == 0);
  CHECK(again.stats().fallbacks == built.stats().fallbacks);
  for (size_t a = 0; a < m.atlases.size(); ++a)
    for (int l = 0; l < built.levels(a); ++l)
      for (int k = 0; k < 3; ++k) CHECK(again.oriented_level(a, l, k) == built.oriented_level(a, l, k));

  // Damaged files: truncated at several places, and a byte flipped in a count.
  const auto bytes = std::filesystem::file_size(file);
  for (std::uintmax_t cut : {std::uintmax_t(5), std::uintmax_t(40), bytes / 2, bytes - 1}) {
    const auto part = dir / "cut.batch";
    std::filesystem::copy_file(file, part, std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(part, cut);
    CAPTURE(cut);
    CHECK_FALSE(queries::load_batch_state(part, "key one").has_value());
  }
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(8 + 4 + 8 + 7 + 8 + 4 + 4 + 8 - 1);  // the last byte of the first atlas's slot count
    f.put(char(0x7f));
  }
  CHECK_FALSE(queries::load_batch_state(file, "key one").has_value());
  CHECK_FALSE(queries::load_batch_state(dir / "absent.batch", "key one").has_value());
  std::filesystem::remove_all(dir);
}

TEST_CASE("batch cache: the key follows the model's bytes and the tolerance; the folder keeps its size") {
  const auto dir = temp_dir();
  const auto model = dir / "model.igs";
  std::ofstream(model) << "one";
  const std::string k1 = queries::batch_cache_key(model, 1e-3, 1 << 22, 4096, "llvmpipe");
  CHECK(k1 == queries::batch_cache_key(model, 1e-3, 1 << 22, 4096, "llvmpipe"));
  CHECK(k1 != queries::batch_cache_key(model, std::nextafter(1e-3, 1.0), 1 << 22, 4096, "llvmpipe"));
  CHECK(k1 != queries::batch_cache_key(model, 1e-3, 1 << 22, 4096, "another GPU"));
  std::ofstream(model) << "two";  // the same length, other bytes
  CHECK(k1 != queries::batch_cache_key(model, 1e-3, 1 << 22, 4096, "llvmpipe"));
  CHECK_THROWS_AS((void)queries::file_fingerprint(dir / "absent.igs"), std::runtime_error);
  CHECK(queries::batch_cache_file(dir, k1).extension() == ".batch");

  // Three files of 100 bytes' worth of state under a limit of 2: the oldest goes.
  queries::PointBatchState empty;
  const auto a = dir / "a.batch", b = dir / "b.batch", c = dir / "c.batch";
  REQUIRE(queries::save_batch_state(a, "a", empty).empty());
  const auto one = std::filesystem::file_size(a);
  std::filesystem::last_write_time(a, std::filesystem::file_time_type::clock::now() - std::chrono::hours(2));
  REQUIRE(queries::save_batch_state(b, "b", empty).empty());
  std::filesystem::last_write_time(b, std::filesystem::file_time_type::clock::now() - std::chrono::hours(1));
  REQUIRE(queries::save_batch_state(c, "c", empty, 2 * one).empty());
  CHECK_FALSE(std::filesystem::exists(a));
  CHECK(std::filesystem::exists(b));
  CHECK(std::filesystem::exists(c));
  // A folder that cannot be made: the reason, no exception.
  CHECK_FALSE(queries::save_batch_state(model / "sub" / "x.batch", "x", empty).empty());
  std::filesystem::remove_all(dir);
}
