#include "queries/batch_cache.h"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <span>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace queries {
namespace {

/// Bumped whenever the stored arrays or the way PointBatch builds them change.
constexpr uint32_t kFormat = 2;
constexpr char kMagic[8] = {'N', 'G', 'L', 'B', 'A', 'T', 'C', 'H'};

uint64_t fnv1a(const void* data, size_t n, uint64_t h = 1469598103934665603ULL) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ULL;
  return h;
}

/// Size and modification time of the running executable: a rebuilt program starts a new cache.
std::string executable_stamp() {
  struct stat st {};
  if (::stat("/proc/self/exe", &st) != 0) return "unknown";
  return fmt::format("{}-{}.{}", st.st_size, st.st_mtim.tv_sec, st.st_mtim.tv_nsec);
}

class Writer {
 public:
  explicit Writer(std::ofstream& out) : out_(out) {}
  template <class T>
  void value(T v) {
    out_.write(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void array(std::span<const T> v) {
    value(uint64_t(v.size()));
    values(v);
  }
  template <class T>
  void values(std::span<const T> v) {
    out_.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
  }

 private:
  std::ofstream& out_;
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
                     kFormat, NURBSGL_VERSION, executable_stamp(), file_fingerprint(model), grid_tolerance,
                     max_samples, atlas_side, renderer);
}

std::filesystem::path batch_cache_file(const std::filesystem::path& directory, const std::string& key) {
  return directory / fmt::format("{:016x}.batch", fnv1a(key.data(), key.size()));
}

std::optional<PointBatchState> load_batch_state(const std::filesystem::path& file, const std::string& key) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  Reader r(in, size);
  char magic[sizeof kMagic];
  uint32_t format = 0;
  std::vector<char> stored_key;
  for (char& c : magic)
    if (!r.value(c)) return std::nullopt;
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0 || !r.value(format) || format != kFormat ||
      !r.array(stored_key) || std::string(stored_key.begin(), stored_key.end()) != key)
    return std::nullopt;
  PointBatchState s;
  uint64_t atlases = 0;
  if (!r.value(atlases) || atlases > r.left()) return std::nullopt;
  for (uint64_t a = 0; a < atlases; ++a) {
    PointBatchState::Atlas& at = s.atlases.emplace_back();
    uint64_t slots = 0;
    if (!r.value(at.plan.width) || !r.value(at.plan.height) || !r.value(slots) || slots > r.left()) return std::nullopt;
    for (uint64_t k = 0; k < slots; ++k) {
      AtlasSlot& sl = at.plan.slots.emplace_back();
      if (!r.value(sl.face) || !r.value(sl.x) || !r.value(sl.y) || !r.value(sl.width) || !r.value(sl.height))
        return std::nullopt;
    }
    if (!r.value(at.w0) || !r.value(at.h0) || !r.value(at.levels) || at.levels < 1 || at.levels > 32) return std::nullopt;
    uint8_t sparse = 0;
    if (!r.value(sparse) || sparse > 1) return std::nullopt;
    if (sparse) {  // the slots' texels only, the rest the outside values
      long long inside = 0;
      for (const AtlasSlot& sl : at.plan.slots) {
        if (sl.x < 0 || sl.y < 0 || sl.width < 0 || sl.height < 0 || sl.x + sl.width > at.plan.width ||
            sl.y + sl.height > at.plan.height)
          return std::nullopt;
        inside += static_cast<long long>(sl.width) * sl.height;
      }
      // (no damaged size asks for much more memory than the file holds: atlases pad by 64 at most)
      const long long texels = static_cast<long long>(at.plan.width) * at.plan.height;
      if (at.plan.width < 0 || at.plan.height < 0 || texels > 256 * inside + 65536 ||
          uint64_t(inside) * 32 > r.left())
        return std::nullopt;
      for (const TexelArray& a : kTexelArrays) {
        std::vector<float> compact;
        if (!r.array(compact) || compact.size() != size_t(inside) * a.components) return std::nullopt;
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
        if (!r.array(at.*a.member)) return std::nullopt;
    }
    for (std::vector<float>* v : {&at.trim_head, &at.trim_segs})
      if (!r.array(*v)) return std::nullopt;
    for (int l = 0; l < at.levels; ++l) {
      PointBatchState::Level& level = at.obb.emplace_back();
      if (!r.array(level.texels)) return std::nullopt;
      for (auto& b : level.boxes)
        if (!r.array(b)) return std::nullopt;
    }
  }
  if (r.left() != 0) return std::nullopt;
  return s;
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
      for (const AtlasSlot& sl : plan.slots) w.value(sl.face), w.value(sl.x), w.value(sl.y), w.value(sl.width), w.value(sl.height);
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
