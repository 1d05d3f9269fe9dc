#pragma once
/// \file parallel.h
/// The two ways work is spread over the CPU's threads (the calling thread is always one of them):
///  - parallel_for: indices handed out by an atomic counter, for work whose result does not depend
///    on which thread did it (per-index outputs), with uneven costs (faces, surface samples);
///  - for_shares: contiguous shares of an index range, so that a per-share result merged in share
///    order is the sequential one whatever the thread count (sums, lists, minima with ties).
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace nurbs {

/// `requested` threads, or one per hardware thread when it is 0 or less.
[[nodiscard]] inline int thread_count(int requested) {
  return requested > 0 ? requested : std::max(1, int(std::thread::hardware_concurrency()));
}

/// body(k, thread) for every k in [0, n), on thread_count(threads) threads at most (no more than
/// there are chunks), `chunk` consecutive k at a time; thread 0 is the calling thread.
template <class F>
void parallel_for(size_t n, int threads, F&& body, size_t chunk = 1) {
  chunk = std::max<size_t>(chunk, 1);
  const int used = int(std::min<size_t>(size_t(thread_count(threads)), (n + chunk - 1) / chunk));
  std::atomic<size_t> next{0};
  auto work = [&](int t) {
    for (size_t i; (i = next.fetch_add(chunk)) < n;)
      for (size_t k = i; k < std::min(n, i + chunk); ++k) body(k, t);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < used; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& th : pool) th.join();
}

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

}  // namespace nurbs
