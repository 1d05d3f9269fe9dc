#pragma once
/// \file parallel.h
/// Contiguous shares of an index range over the hardware threads, so that a per-share result
/// merged in share order is the sequential one whatever the thread count.
#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace queries {

/// Shares for n items of at least `min_share` each, at most one per hardware thread.
[[nodiscard]] inline size_t share_count(size_t n, size_t min_share) {
  return std::clamp<size_t>(n / std::max<size_t>(min_share, 1), 1, std::max(1u, std::thread::hardware_concurrency()));
}

/// Runs f(share, begin, end) for `shares` contiguous shares of [0, n), share 0 on this thread.
template <class F>
void for_shares(size_t n, size_t shares, F&& f) {
  std::vector<std::thread> pool;
  for (size_t t = 1; t < shares; ++t)
    pool.emplace_back([&f, t, n, shares] { f(t, t * n / shares, (t + 1) * n / shares); });
  f(size_t(0), size_t(0), n / shares);
  for (std::thread& th : pool) th.join();
}

}  // namespace queries
