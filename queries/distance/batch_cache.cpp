#include "queries/distance/batch_cache.h"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

namespace queries {
namespace {

/// Bumped whenever the stored arrays, the way PointBatch builds them or the file's layout change
/// (3: the trailing checksum).
constexpr uint32_t kFormat = 3;
constexpr char kMagic[8] = {'N', 'G', 'L', 'B', 'A', 'T', 'C', 'H'};
/// The magic, the format, the key's length and the checksum: no file is shorter.
constexpr uint64_t kLeastBytes = sizeof kMagic + sizeof kFormat + 8 + 8;

uint64_t fnv1a(const void* data, size_t n, uint64_t h = 1469598103934665603ULL) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ULL;
  return h;
}

/// A bijective 64-bit mix (xor-shifts and odd multipliers): every input bit reaches every output bit.
uint64_t avalanche(uint64_t x) {
  x ^= x >> 31;
  x *= 0xd6e8feb86659fd93ULL;
  x ^= x >> 29;
  x *= 0xa0761d6478bd642fULL;
  return x ^ (x >> 32);
}

/// A 64-bit checksum of a byte stream fed in pieces of any size. Four lanes take the 8-byte words
/// in turn, 8 bytes per multiply (a cache file of hundreds of MB is checked at memory speed);
/// each step is a bijection of its lane for a given word and of the word for a given lane, and the
/// lanes are folded by bijections too, so two streams of one length that differ in a single word
/// always differ in the sum. Catches damage, not forgery.
class Checksum {
 public:
  void update(const void* data, size_t n) {
    if (n == 0) return;  // an empty array's data() may be null, which memcpy must not get
    const auto* p = static_cast<const unsigned char*>(data);
    length_ += n;
    if (fill_ > 0) {
      const size_t take = std::min(n, sizeof stripe_ - fill_);
      std::memcpy(stripe_ + fill_, p, take);
      fill_ += take, p += take, n -= take;
      if (fill_ < sizeof stripe_) return;
      consume(lanes_, stripe_);
      fill_ = 0;
    }
    for (; n >= sizeof stripe_; p += sizeof stripe_, n -= sizeof stripe_) consume(lanes_, p);
    if (n > 0) std::memcpy(stripe_, p, n);
    fill_ = n;
  }
  [[nodiscard]] uint64_t value() const {
    uint64_t lanes[4] = {lanes_[0], lanes_[1], lanes_[2], lanes_[3]};
    if (fill_ > 0) {  // the tail zero-padded (the length tells it from real zeros)
      unsigned char last[sizeof stripe_] = {};
      std::memcpy(last, stripe_, fill_);
      consume(lanes, last);
    }
    uint64_t h = avalanche(length_ ^ 0x6e75726273676c31ULL);
    for (const uint64_t lane : lanes) h = avalanche(h ^ lane);
    return h;
  }

 private:
  static void consume(uint64_t (&lanes)[4], const unsigned char* p) {
    for (int k = 0; k < 4; ++k) {
      uint64_t w = 0;
      std::memcpy(&w, p + 8 * k, 8);
      lanes[k] = std::rotl(lanes[k] ^ (w * 0x9fb21c651e98df25ULL), 27) * 0xc4ceb9fe1a85ec53ULL;
    }
  }
  uint64_t lanes_[4] = {0x243f6a8885a308d3ULL, 0x13198a2e03707344ULL, 0xa4093822299f31d0ULL, 0x082efa98ec4e6c89ULL};
  unsigned char stripe_[32] = {};
  size_t fill_ = 0;
  uint64_t length_ = 0;
};

/// Size and modification time of the running executable: a rebuilt program starts a new cache.
std::string executable_stamp() {
  struct stat st {};
  if (::stat("/proc/self/exe", &st) != 0) return "unknown";
  return fmt::format("{}-{}.{}", st.st_size, st.st_mtim.tv_sec, st.st_mtim.tv_nsec);
}

/// Writes values and arrays, summing every byte written (checksum() goes last in the file).
class Writer {
 public:
  explicit Writer(std::ofstream& out) : out_(out) {}
  template <class T>
  void value(T v) {
    values(std::span<const T>(&v, 1));
  }
  template <class T>
  void array(std::span<const T> v) {
    value(uint64_t(v.size()));
    values(v);
  }
  template <class T>
  void values(std::span<const T> v) {
    sum_.update(v.data(), v.size() * sizeof(T));
    out_.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
  }
  [[nodiscard]] uint64_t checksum() const { return sum_.value(); }

 private:
  std::ofstream& out_;
  Checksum sum_;
};

/// Reads from a file of known size; every count is checked against the bytes left, so a damaged
/// file never asks for more memory than it holds.
class Reader {
 public:
  Reader(std::ifstream& in, uint64_t size) : in_(in), left_(size) {}
  template <class T>
  bool value(T& v) {
    if (left_ < sizeof v) return false;
    in_.read(reinterpret_cast<char*>(&v), sizeof v);
    left_ -= sizeof v;
    return bool(in_);
  }
  template <class T>
  bool array(std::vector<T>& v) {
    uint64_t n = 0;
    if (!value(n) || n > left_ / sizeof(T)) return false;
    v.resize(size_t(n));
    in_.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(T)));
    left_ -= n * sizeof(T);
    return bool(in_);
  }
  [[nodiscard]] uint64_t left() const { return left_; }

 private:
  std::ifstream& in_;
  uint64_t left_;
};

/// Whether the last 8 bytes of `in` (a file of `size` bytes) are the checksum of all bytes before
/// them. Reads the file once in pieces of 1 MiB, allocating nothing in proportion to it.
bool checksum_matches(std::ifstream& in, uint64_t size) {
  Checksum sum;
  std::vector<char> buffer(size_t(1) << 20);
  in.seekg(0);
  for (uint64_t left = size - 8; left > 0;) {
    const auto n = size_t(std::min<uint64_t>(left, buffer.size()));
    if (!in.read(buffer.data(), std::streamsize(n))) return false;
    sum.update(buffer.data(), n);
    left -= n;
  }
  uint64_t stored = 0;
  return in.read(reinterpret_cast<char*>(&stored), sizeof stored) && stored == sum.value();
}

/// Removes the oldest cache files of `dir` until they hold at most max_bytes.
void trim_directory(const std::filesystem::path& dir, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  struct Entry {
    fs::path path;
    fs::file_time_type time;
    std::uintmax_t bytes;
  };
  std::vector<Entry> files;
  std::uintmax_t total = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() != ".batch" || !e.is_regular_file(ec)) continue;
    const std::uintmax_t bytes = e.file_size(ec);
    files.push_back({e.path(), e.last_write_time(ec), bytes});
    total += bytes;
  }
  std::sort(files.begin(), files.end(), [](const Entry& a, const Entry& b) { return a.time < b.time; });
  for (const Entry& f : files) {
    if (total <= max_bytes) break;
    if (fs::remove(f.path, ec)) total -= f.bytes;
  }
}

/// The per-texel arrays of an atlas (components per texel) and their values outside every slot.
struct TexelArray {
  std::vector<float> PointBatchState::Atlas::*member;
  std::span<const float> PointBatchStateView::Atlas::*view;
  size_t components;
  float outside;
};
using S = PointBatchState::Atlas;
using V = PointBatchStateView::Atlas;
constexpr TexelArray kTexelArrays[] = {{&S::samples, &V::samples, 4, 0.0f},
                                       {&S::slot_of, &V::slot_of, 1, -1.0f},
                                       {&S::mask, &V::mask, 1, 0.0f},
                                       {&S::crossed, &V::crossed, 1, 0.0f},
                                       {&S::trim_cell, &V::trim_cell, 1, 0.0f}};

/// Calls f(texel) for every texel inside a slot, slot by slot, row by row.
template <class F>
void for_slot_texels(const AtlasPlan& plan, F&& f) {
  for (const AtlasSlot& sl : plan.slots)
    for (int j = 0; j < sl.height; ++j)
      for (int i = 0; i < sl.width; ++i) f(size_t(sl.y + j) * size_t(plan.width) + size_t(sl.x + i));
}

/// Whether every texel outside the slots holds the arrays' outside values (what the atlas
/// evaluation and the trim fill leave there): then only the slots' texels are stored.
bool padding_is_empty(const PointBatchStateView::Atlas& at) {
  const size_t texels = size_t(at.plan->width) * size_t(at.plan->height);
  std::vector<char> inside(texels, 0);
  for_slot_texels(*at.plan, [&](size_t t) { inside[t] = 1; });
  for (const TexelArray& a : kTexelArrays) {
    const std::span<const float> v = at.*a.view;
    if (v.size() != texels * a.components) return false;
    for (size_t t = 0; t < texels; ++t)
      if (!inside[t])
        for (size_t c = 0; c < a.components; ++c)
          if (v[t * a.components + c] != a.outside) return false;
  }
  return true;
}

/// Whether `x` is a whole number in [lo, hi] (NaN is not).
bool whole_in(float x, double lo, double hi) { return x >= lo && x <= hi && std::floor(x) == x; }

/// Why the arrays of `at` (read from a file) cannot be the state PointBatch built for its plan, or
/// "" when they can: the sizes PointBatch(gpu, m, state) and the queries assume, and every index
/// (slot, trimmed cell, trim segment, pyramid texel) inside what it indexes, so that even a damaged
/// file whose checksum happened to match reads out of no array.
std::string check_atlas(const PointBatchState::Atlas& at) {
  const AtlasPlan& plan = at.plan;
  const size_t texels = size_t(plan.width) * size_t(plan.height);
  const int w0 = int(std::bit_ceil(unsigned(plan.width))), h0 = int(std::bit_ceil(unsigned(plan.height)));
  int levels = 1;
  while ((std::max(w0, h0) >> levels) > 0) ++levels;
  if (at.w0 != w0 || at.h0 != h0 || at.levels != levels)
    return fmt::format("pyramid {}x{} with {} levels for an atlas of {}x{}", at.w0, at.h0, at.levels, plan.width,
                       plan.height);
  for (const TexelArray& a : kTexelArrays)
    if ((at.*a.member).size() != texels * a.components) return "a per-texel array of another size than its atlas";
  const auto slots = double(plan.slots.size());
  const size_t heads = at.trim_head.size() / 4, segs = at.trim_segs.size() / 4;
  for (size_t t = 0; t < texels; ++t)
    if (!(at.slot_of[t] == -1.0f || whole_in(at.slot_of[t], 0.0, slots - 1.0)) ||
        !whole_in(at.trim_cell[t], 0.0, double(heads)))
      return fmt::format("texel {}: a slot or trimmed-cell index outside its array", t);
  if (at.trim_head.size() % 4 != 0 || at.trim_segs.size() % 4 != 0) return "trim arrays not of 4 floats per entry";
  for (size_t k = 0; k < heads; ++k) {
    const float* h = &at.trim_head[4 * k];
    if (!whole_in(h[0], 0.0, double(segs)) || !whole_in(h[1], 0.0, double(segs)) ||
        !whole_in(h[2], 0.0, double(segs)) || double(h[0]) + h[1] + h[2] > double(segs))
      return fmt::format("trimmed cell {}: segments beyond the {} stored", k, segs);
  }
  for (int l = 0; l < levels; ++l) {
    const PointBatchState::Level& level = at.obb[size_t(l)];
    const uint64_t n = uint64_t(std::max(1, w0 >> l)) * uint64_t(std::max(1, h0 >> l));
    for (const auto& b : level.boxes)
      if (b.size() != 4 * level.texels.size()) return fmt::format("pyramid level {}: boxes of another count", l);
    for (size_t t = 0; t < level.texels.size(); ++t)
      if (level.texels[t] >= n || (t > 0 && level.texels[t] <= level.texels[t - 1]))
        return fmt::format("pyramid level {}: a texel outside the level or out of order", l);
  }
  return {};
}

/// Reads the atlases that follow the key into `s`; why they cannot be a state, or "".
std::string read_atlases(Reader& r, PointBatchState& s) {
  uint64_t atlases = 0;
  if (!r.value(atlases) || atlases > r.left()) return "an atlas count beyond the file";
  for (uint64_t a = 0; a < atlases; ++a) {
    const std::string where = fmt::format("atlas {}: ", a);
    PointBatchState::Atlas& at = s.atlases.emplace_back();
    uint64_t slots = 0;
    if (!r.value(at.plan.width) || !r.value(at.plan.height) || !r.value(slots) || slots > r.left())
      return where + "a slot count beyond the file";
    // (GL textures are at most 32768 texels a side)
    if (at.plan.width < 1 || at.plan.height < 1 || at.plan.width > 32768 || at.plan.height > 32768)
      return where + fmt::format("size {}x{}", at.plan.width, at.plan.height);
    long long inside = 0;
    for (uint64_t k = 0; k < slots; ++k) {
      AtlasSlot& sl = at.plan.slots.emplace_back();
      if (!r.value(sl.face) || !r.value(sl.x) || !r.value(sl.y) || !r.value(sl.width) || !r.value(sl.height))
        return where + "slots beyond the file";
      if (sl.x < 0 || sl.y < 0 || sl.width < 0 || sl.height < 0 || sl.x > at.plan.width - sl.width ||
          sl.y > at.plan.height - sl.height)
        return where + fmt::format("slot {} outside the atlas", k);
      inside += static_cast<long long>(sl.width) * sl.height;
    }
    if (!r.value(at.w0) || !r.value(at.h0) || !r.value(at.levels) || at.levels < 1 || at.levels > 32)
      return where + "a pyramid of no or too many levels";
    uint8_t sparse = 0;
    if (!r.value(sparse) || sparse > 1) return where + "neither sparse nor dense";
    if (sparse) {  // the slots' texels only, the rest the outside values
      // (no damaged size asks for much more memory than the file holds: atlases pad by 64 at most)
      const long long texels = static_cast<long long>(at.plan.width) * at.plan.height;
      if (texels > 256 * inside + 65536 || uint64_t(inside) * 32 > r.left())
        return where + "slot texels beyond the file";
      for (const TexelArray& a : kTexelArrays) {
        std::vector<float> compact;
        if (!r.array(compact) || compact.size() != size_t(inside) * a.components)
          return where + "a per-texel array of another size than its slots";
        std::vector<float>& v = at.*a.member;
        v.assign(size_t(texels) * a.components, a.outside);
        size_t k = 0;
        for_slot_texels(at.plan, [&](size_t t) {
          std::copy_n(compact.begin() + ptrdiff_t(k), a.components, v.begin() + ptrdiff_t(t * a.components));
          k += a.components;
        });
      }
    } else {
      for (const TexelArray& a : kTexelArrays)
        if (!r.array(at.*a.member)) return where + "a per-texel array beyond the file";
    }
    for (std::vector<float>* v : {&at.trim_head, &at.trim_segs})
      if (!r.array(*v)) return where + "trim data beyond the file";
    for (int l = 0; l < at.levels; ++l) {
      PointBatchState::Level& level = at.obb.emplace_back();
      if (!r.array(level.texels)) return where + fmt::format("pyramid level {} beyond the file", l);
      for (auto& b : level.boxes)
        if (!r.array(b)) return where + fmt::format("pyramid level {} beyond the file", l);
    }
    if (std::string why = check_atlas(at); !why.empty()) return where + why;
  }
  return {};
}

}  // namespace

std::filesystem::path batch_cache_directory() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::filesystem::path(x) / "nurbsgl";
  if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".cache" / "nurbsgl";
  return {};
}

std::string file_fingerprint(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read the file", file.string()));
  uint64_t h = 1469598103934665603ULL, n = 0;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), std::streamsize(buffer.size()));
    const auto got = size_t(in.gcount());
    h = fnv1a(buffer.data(), got, h);
    n += got;
  }
  return fmt::format("{:016x}-{}", h, n);
}

std::string batch_cache_key(const std::filesystem::path& model, double grid_tolerance, long long max_samples,
                            int atlas_side, const std::string& renderer) {
  return fmt::format("format {} nurbsgl {} exe {} model {} tolerance {:a} max-samples {} atlas-side {} renderer {}",
                     kFormat, NURBSGL_VERSION, executable_stamp(), file_fingerprint(model), grid_tolerance, max_samples,
                     atlas_side, renderer);
}

std::filesystem::path batch_cache_file(const std::filesystem::path& directory, const std::string& key) {
  return directory / fmt::format("{:016x}.batch", fnv1a(key.data(), key.size()));
}

BatchCacheRead load_batch_state(const std::filesystem::path& file, const std::string& key) {
  const auto miss = [](std::string why) { return BatchCacheRead{std::nullopt, std::move(why)}; };
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return {};  // a first run: nothing to say
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) return miss(fmt::format("cannot read its size ({})", ec.message()));
  std::ifstream in(file, std::ios::binary);
  if (!in) return miss("cannot open it");
  if (size < kLeastBytes) return miss(fmt::format("truncated ({} bytes)", size));
  char magic[sizeof kMagic];
  uint32_t format = 0;
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    return miss("not a batch cache file (another magic)");
  if (!in.read(reinterpret_cast<char*>(&format), sizeof format) || format != kFormat)
    return miss(fmt::format("cache format {}, this program reads {}", format, kFormat));
  // Nothing of the content is used before the whole file is known to be what was written.
  if (!checksum_matches(in, size))
    return miss(fmt::format("its checksum does not match its {} bytes (damaged, truncated or extended)", size));
  in.clear();
  in.seekg(sizeof kMagic + sizeof kFormat);
  Reader r(in, size - sizeof kMagic - sizeof kFormat - 8);
  std::vector<char> stored_key;
  if (!r.array(stored_key)) return miss("the key's length exceeds the file");
  if (std::string_view(stored_key.data(), stored_key.size()) != key)
    return miss("it holds another key (another model, tolerance or program)");
  PointBatchState s;
  if (std::string why = read_atlases(r, s); !why.empty()) return miss("inconsistent content: " + why);
  if (r.left() != 0) return miss(fmt::format("{} bytes after the stored state", r.left()));
  return {std::move(s), {}};
}

std::string save_batch_state(const std::filesystem::path& file, const std::string& key,
                             const PointBatchStateView& state, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  if (ec) return fmt::format("cannot create {}: {}", file.parent_path().string(), ec.message());
  const fs::path part = file.string() + fmt::format(".{}.part", ::getpid());
  {
    std::ofstream out(part, std::ios::binary | std::ios::trunc);
    if (!out) return fmt::format("cannot write {}", part.string());
    Writer w(out);
    for (char c : kMagic) w.value(c);
    w.value(kFormat);
    w.array(std::span<const char>(key));
    w.value(uint64_t(state.atlases.size()));
    for (const PointBatchStateView::Atlas& at : state.atlases) {
      const AtlasPlan& plan = *at.plan;
      w.value(plan.width), w.value(plan.height), w.value(uint64_t(plan.slots.size()));
      for (const AtlasSlot& sl : plan.slots)
        w.value(sl.face), w.value(sl.x), w.value(sl.y), w.value(sl.width), w.value(sl.height);
      w.value(at.w0), w.value(at.h0), w.value(at.levels);
      const bool sparse = padding_is_empty(at);
      w.value(uint8_t(sparse));
      long long inside = 0;
      for (const AtlasSlot& sl : plan.slots) inside += static_cast<long long>(sl.width) * sl.height;
      for (const TexelArray& a : kTexelArrays) {
        const std::span<const float> v = at.*a.view;
        if (!sparse) {
          w.array(v);
          continue;
        }
        // The slots' texels, row by row straight from the arrays (as for_slot_texels visits them).
        w.value(uint64_t(inside) * a.components);
        for (const AtlasSlot& sl : plan.slots)
          for (int j = 0; j < sl.height; ++j)
            w.values(v.subspan((size_t(sl.y + j) * size_t(plan.width) + size_t(sl.x)) * a.components,
                               size_t(sl.width) * a.components));
      }
      for (const std::span<const float> v : {at.trim_head, at.trim_segs}) w.array(v);
      for (const PointBatchStateView::Level& level : at.obb) {
        w.array(level.texels);
        for (const auto& b : level.boxes) w.array(b);
      }
    }
    const uint64_t sum = w.checksum();
    out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
    out.flush();
    if (!out) {
      out.close();
      fs::remove(part, ec);
      return fmt::format("cannot write {} (disk full?)", part.string());
    }
  }
  fs::rename(part, file, ec);
  if (ec) {
    fs::remove(part, ec);
    return fmt::format("cannot rename {} to {}", part.string(), file.string());
  }
  trim_directory(file.parent_path(), max_bytes);
  return {};
}

bool state_matches(const PreparedModel& m, const PointBatchState& state) {
  std::vector<int> seen(m.faces.size(), 0);
  for (const PointBatchState::Atlas& at : state.atlases)
    for (const AtlasSlot& sl : at.plan.slots) {
      if (sl.face < 0 || size_t(sl.face) >= m.faces.size() || seen[size_t(sl.face)]++) return false;
      const nurbs::ParamGrid& g = m.grids[size_t(sl.face)].grid;
      if (sl.width != int(g.u.size()) || sl.height != int(g.v.size()) || sl.x < 0 || sl.y < 0 ||
          sl.x + sl.width > at.plan.width || sl.y + sl.height > at.plan.height)
        return false;
    }
  return std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; });
}

}  // namespace queries
