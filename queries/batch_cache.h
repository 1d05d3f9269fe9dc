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
///    evaluation made the samples). The file holds the key; a file whose key differs, that is
///    truncated or whose arrays do not fit is a miss, never an error.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "queries/point_batch.h"

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

/// The state stored under `key` in `file`; nullopt when there is none (absent, another key,
/// truncated, inconsistent).
[[nodiscard]] std::optional<PointBatchState> load_batch_state(const std::filesystem::path& file,
                                                              const std::string& key);

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
