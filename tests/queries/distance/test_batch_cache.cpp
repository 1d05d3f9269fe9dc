// The batched preparation's disk cache (queries/distance/batch_cache.h): a state exported, written, read and
// restored answers every point as the batch it came from, bit for bit; a file of another key, a
// truncated, extended or damaged file, and a state of other grids are misses with a reason, never
// errors and never a state.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "tests/gpgpu/gl_fixture.h"
#include "queries/distance/batch_cache.h"
#include "queries/distance/point_batch.h"
#include "tests/queries/distance/point_batch_fixtures.h"

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
      for (const auto& level : at.obb)
        other += static_cast<long long>(4 * level.texels.size() + 4 * 12 * level.texels.size());
    }
    const auto bytes = static_cast<long long>(std::filesystem::file_size(file));
    MESSAGE("cache file " << bytes << " bytes; " << slot_texels << " slot texels of " << atlas_texels);
    REQUIRE(slot_texels < atlas_texels);
    CHECK(bytes <= 32 * slot_texels + other + 4096);
  }
  CHECK_FALSE(queries::load_batch_state(file, "key two").state.has_value());  // another model or tolerance
  std::optional<queries::PointBatchState> state = queries::load_batch_state(file, "key one").state;
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
    CHECK_FALSE(queries::load_batch_state(part, "key one").state.has_value());
  }
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(8 + 4 + 8 + 7 + 8 + 4 + 4 + 8 - 1);  // the last byte of the first atlas's slot count
    f.put(char(0x7f));
  }
  CHECK_FALSE(queries::load_batch_state(file, "key one").state.has_value());
  CHECK_FALSE(queries::load_batch_state(dir / "absent.batch", "key one").state.has_value());
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

namespace {

/// A small state in the shape PointBatch exports, without a GL context: two atlases, one whose
/// padding holds the outside values (stored sparse) and one whose padding does not (stored dense),
/// a trimmed cell with its segments, and a four-level pyramid.
queries::PointBatchState small_state() {
  queries::PointBatchState s;
  for (int a = 0; a < 2; ++a) {
    queries::PointBatchState::Atlas& at = s.atlases.emplace_back();
    at.plan.width = 6, at.plan.height = 5;
    at.plan.slots = {{2 * a, 0, 0, 3, 3}, {2 * a + 1, 3, 0, 3, 5}};
    at.w0 = 8, at.h0 = 8, at.levels = 4;
    const size_t texels = 30;
    at.samples.assign(4 * texels, 0.0f), at.slot_of.assign(texels, -1.0f), at.mask.assign(texels, 0.0f);
    at.crossed.assign(texels, 0.0f), at.trim_cell.assign(texels, 0.0f);
    for (int k = 0; k < 2; ++k) {
      const queries::AtlasSlot& sl = at.plan.slots[size_t(k)];
      for (int j = 0; j < sl.height; ++j)
        for (int i = 0; i < sl.width; ++i) {
          const size_t t = size_t(sl.y + j) * 6 + size_t(sl.x + i);
          for (size_t c = 0; c < 4; ++c) at.samples[4 * t + c] = 0.25f * float(t) + float(c) + 100.0f * float(a);
          at.slot_of[t] = float(k), at.mask[t] = float((i + j) % 2), at.crossed[t] = float(i == 1);
        }
    }
    if (a == 1) at.samples[4 * 24] = 7.0f;  // a padding texel (0, 4) off its outside value: dense
    at.trim_cell[7] = 1.0f;
    at.trim_head = {0.0f, 1.0f, 1.0f, 1.0f};
    at.trim_segs = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f};
    for (int l = 0; l < 4; ++l) {
      queries::PointBatchState::Level& level = at.obb.emplace_back();
      level.texels = {0u, uint32_t(l < 3 ? 1 : 0)};
      if (l == 3) level.texels.pop_back();
      for (size_t k = 0; k < 3; ++k)
        for (size_t t = 0; t < 4 * level.texels.size(); ++t)
          level.boxes[k].push_back(float(l * 100 + int(k) * 10) + float(t));
    }
  }
  return s;
}

bool same_state(const queries::PointBatchState& x, const queries::PointBatchState& y) {
  if (x.atlases.size() != y.atlases.size()) return false;
  for (size_t a = 0; a < x.atlases.size(); ++a) {
    const auto &p = x.atlases[a], &q = y.atlases[a];
    if (p.plan.width != q.plan.width || p.plan.height != q.plan.height || p.plan.slots.size() != q.plan.slots.size() ||
        p.w0 != q.w0 || p.h0 != q.h0 || p.levels != q.levels || p.samples != q.samples || p.slot_of != q.slot_of ||
        p.mask != q.mask || p.crossed != q.crossed || p.trim_cell != q.trim_cell || p.trim_head != q.trim_head ||
        p.trim_segs != q.trim_segs || p.obb.size() != q.obb.size())
      return false;
    for (size_t k = 0; k < p.plan.slots.size(); ++k) {
      const auto &u = p.plan.slots[k], &v = q.plan.slots[k];
      if (u.face != v.face || u.x != v.x || u.y != v.y || u.width != v.width || u.height != v.height) return false;
    }
    for (size_t l = 0; l < p.obb.size(); ++l)
      if (p.obb[l].texels != q.obb[l].texels || p.obb[l].boxes != q.obb[l].boxes) return false;
  }
  return true;
}

std::string bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace

TEST_CASE("batch cache: a file that differs from the one written in any byte is a miss with the reason") {
  const auto dir = temp_dir() / "damage";
  const auto file = dir / "state.batch", copy = dir / "copy.batch";
  const queries::PointBatchState saved = small_state();
  REQUIRE(queries::save_batch_state(file, "the key", saved).empty());
  CHECK_FALSE(std::filesystem::exists(file.string() + "." + std::to_string(::getpid()) + ".part"));
  const std::string intact = bytes_of(file);
  REQUIRE(intact.size() > 600);
  {
    const queries::BatchCacheRead read = queries::load_batch_state(file, "the key");
    CHECK(read.problem.empty());
    REQUIRE(read.state.has_value());
    CHECK(same_state(*read.state, saved));
  }
  const size_t n = intact.size();
  // header: magic, format, key length, key; body: sparse atlas, dense atlas; the checksum's bytes
  struct Flip {
    size_t at;
    const char* reason;
  };
  for (const Flip f :
       {Flip{0, "another magic"}, Flip{8, "cache format"}, Flip{12, "checksum"}, Flip{22, "checksum"},
        Flip{n / 3, "checksum"}, Flip{n / 2, "checksum"}, Flip{n - 9, "checksum"}, Flip{n - 1, "checksum"}}) {
    for (const unsigned char mask : {0x01, 0x80, 0xff}) {
      std::string bytes = intact;
      bytes[f.at] = char(bytes[f.at] ^ mask);
      write_bytes(copy, bytes);
      const queries::BatchCacheRead read = queries::load_batch_state(copy, "the key");
      CAPTURE(f.at);
      CAPTURE(int(mask));
      CAPTURE(read.problem);
      CHECK_FALSE(read.state.has_value());
      CHECK(read.problem.find(f.reason) != std::string::npos);
    }
  }
  // Every single flipped bit of the body (the checksum's bijective lanes see each one).
  int used = 0;
  for (size_t at = 24; at < n; at += 7)
    for (int bit = 0; bit < 8; bit += 3) {
      std::string bytes = intact;
      bytes[at] = char(bytes[at] ^ (1 << bit));
      write_bytes(copy, bytes);
      used += queries::load_batch_state(copy, "the key").state.has_value();
    }
  CHECK(used == 0);
  for (const size_t cut : {size_t(0), size_t(5), size_t(27), n / 2, n - 8, n - 1}) {
    write_bytes(copy, intact.substr(0, cut));
    const queries::BatchCacheRead read = queries::load_batch_state(copy, "the key");
    CAPTURE(cut);
    CAPTURE(read.problem);
    CHECK_FALSE(read.state.has_value());
    CHECK((read.problem.find("truncated") != std::string::npos || read.problem.find("checksum") != std::string::npos));
  }
  for (const std::string& tail : {std::string(1, '\0'), std::string("x"), intact}) {
    write_bytes(copy, intact + tail);
    const queries::BatchCacheRead read = queries::load_batch_state(copy, "the key");
    CAPTURE(tail.size());
    CAPTURE(read.problem);
    CHECK_FALSE(read.state.has_value());
    CHECK(read.problem.find("checksum") != std::string::npos);
  }
  {
    const queries::BatchCacheRead read = queries::load_batch_state(file, "another key");
    CHECK_FALSE(read.state.has_value());
    CHECK(read.problem.find("another key") != std::string::npos);
  }
  {
    std::string bytes = intact;  // a file of the previous layout (format 2, no checksum)
    bytes[8] = 2;
    write_bytes(copy, bytes);
    const queries::BatchCacheRead read = queries::load_batch_state(copy, "the key");
    CHECK_FALSE(read.state.has_value());
    CHECK(read.problem == "cache format 2, this program reads 3");
  }
  {
    const queries::BatchCacheRead read = queries::load_batch_state(dir / "absent.batch", "the key");
    CHECK_FALSE(read.state.has_value());
    CHECK(read.problem.empty());  // a first run: nothing to warn about
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("batch cache: a file whose checksum matches still reads no index outside its arrays") {
  // Written by save_batch_state, so the checksum is right: what the reader's structural checks see.
  const auto dir = temp_dir() / "structure";
  const auto file = dir / "state.batch";
  struct Case {
    const char* name;
    void (*damage)(queries::PointBatchState&);
    const char* reason;
  };
  const Case cases[] = {
      {"slot index", [](queries::PointBatchState& s) { s.atlases[0].slot_of[4] = 2.0f; }, "slot or trimmed-cell index"},
      {"trimmed cell", [](queries::PointBatchState& s) { s.atlases[1].trim_cell[8] = 2.0f; },
       "slot or trimmed-cell index"},
      {"NaN index", [](queries::PointBatchState& s) { s.atlases[1].slot_of[8] = std::nanf(""); },
       "slot or trimmed-cell index"},
      {"segments", [](queries::PointBatchState& s) { s.atlases[0].trim_head[2] = 2.0f; }, "segments beyond"},
      {"texel order",
       [](queries::PointBatchState& s) { std::swap(s.atlases[0].obb[1].texels[0], s.atlases[0].obb[1].texels[1]); },
       "out of order"},
      {"texel outside", [](queries::PointBatchState& s) { s.atlases[1].obb[2].texels[1] = 4; }, "outside the level"},
      {"boxes", [](queries::PointBatchState& s) { s.atlases[0].obb[0].boxes[2].pop_back(); }, "boxes of another count"},
      {"pyramid size", [](queries::PointBatchState& s) { s.atlases[0].w0 = 1 << 20; }, "pyramid"},
  };
  for (const Case& c : cases) {
    queries::PointBatchState s = small_state();
    c.damage(s);
    REQUIRE(queries::save_batch_state(file, "k", s).empty());
    const queries::BatchCacheRead read = queries::load_batch_state(file, "k");
    CAPTURE(c.name);
    CAPTURE(read.problem);
    CHECK_FALSE(read.state.has_value());
    CHECK(read.problem.find("inconsistent content") != std::string::npos);
    CHECK(read.problem.find(c.reason) != std::string::npos);
  }
  std::filesystem::remove_all(dir);
}
