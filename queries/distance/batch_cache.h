#pragma once
/// \file batch_cache.h
/// The batched point query's preparation kept on disk (beyond the paper): a second run on the same
/// model and tolerance reads the atlases' samples, the trimmed cells and the oriented pyramid
/// (PointBatchState) instead of evaluating, filling and building them.
///  - Where: $XDG_CACHE_HOME/nurbsgl, else $HOME/.cache/nurbsgl; one file per key, named by the
///    key's hash; written to a temporary name and renamed (a reader never sees half a file); the
///    oldest files removed once the folder holds more than kBatchCacheBytes.
///  - Key: the cache format, the program (version, and the size and time of the running
///    executable: a rebuild starts afresh), the model file's bytes (FNV-1a 64 and length), the
///    grid tolerance (exact bits), the sample limit, the atlas side and the GL renderer (its float
///    evaluation made the samples).
///  - Trust: the file holds the key and ends with a 64-bit checksum of every byte before it. A
///    file is used only when its magic, format, checksum and key agree, and its counts and
///    indices fit the bytes and the arrays they describe; any other file is a miss with a reason
///    (the caller warns and rebuilds it), never an error and never a partly read state.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "queries/distance/point_batch.h"

namespace queries {

/// The most bytes of cache files kept in the folder (the oldest go first).
inline constexpr std::uintmax_t kBatchCacheBytes = std::uintmax_t(2) << 30;

/// $XDG_CACHE_HOME/nurbsgl, else $HOME/.cache/nurbsgl; empty when neither variable is set.
[[nodiscard]] std::filesystem::path batch_cache_directory();

/// FNV-1a 64 of the file's bytes and its length, as hex; throws std::runtime_error naming the
/// file when it cannot be read.
[[nodiscard]] std::string file_fingerprint(const std::filesystem::path& file);

/// The key of a batched preparation (see the file comment).
[[nodiscard]] std::string batch_cache_key(const std::filesystem::path& model, double grid_tolerance,
                                          long long max_samples, int atlas_side, const std::string& renderer);

/// The cache file of `key` in `directory`.
[[nodiscard]] std::filesystem::path batch_cache_file(const std::filesystem::path& directory, const std::string& key);

/// What load_batch_state found in a cache file.
struct BatchCacheRead {
  std::optional<PointBatchState> state;  ///< the stored state, when the file verified
  /// Why an existing file was not used (truncated, checksum, format, key, inconsistent content);
  /// empty when it was used or when there is no file.
  std::string problem;
};

/// The state stored under `key` in `file`: read only after the whole file's checksum, magic,
/// format and key agree, and checked for counts and indices that fit (so that no damage can make
/// a query read outside an array or allocate beyond the file's size).
[[nodiscard]] BatchCacheRead load_batch_state(const std::filesystem::path& file, const std::string& key);

/// Writes `state` under `key` to `file` (creating its folder), then removes the folder's oldest
/// cache files beyond `max_bytes`. Returns an empty string, or why the file could not be written.
std::string save_batch_state(const std::filesystem::path& file, const std::string& key,
                             const PointBatchStateView& state, std::uintmax_t max_bytes = kBatchCacheBytes);
inline std::string save_batch_state(const std::filesystem::path& file, const std::string& key,
                                    const PointBatchState& state, std::uintmax_t max_bytes = kBatchCacheBytes) {
  return save_batch_state(file, key, view(state), max_bytes);
}

/// Whether `state`'s atlas plans are those prepare_atlases would make for `m`'s grids: every slot
/// of a face's grid size, every face once.
[[nodiscard]] bool state_matches(const PreparedModel& m, const PointBatchState& state);

}  // namespace queries
