#pragma once
/// \file profiler.h
/// Per-named-pass timing: GPU time from GL_TIME_ELAPSED queries and CPU wall time, accumulated so
/// a query can print a breakdown like Table 2 of Krishnamurthy et al. Queries are resolved lazily
/// in report(), so timing does not stall the pipeline; with sync on, every pass ends with glFinish
/// and the CPU wall time is the pass's true latency.
#include <GL/glcorearb.h>

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

namespace gpgpu {

class Profiler {
 public:
  struct Entry {
    std::string name;
    int calls = 0;
    double gpu_ms = 0.0;  ///< NaN when timer queries are unavailable
    double cpu_ms = 0.0;
  };

  explicit Profiler(bool timer_queries = true) : timer_queries_(timer_queries) {}
  ~Profiler();
  Profiler(const Profiler&) = delete;
  Profiler& operator=(const Profiler&) = delete;

  void set_enabled(bool on) { enabled_ = on; }
  /// Off when the context has no GL_TIME_ELAPSED counter: gpu_ms is then NaN.
  void set_timer_queries(bool on) { timer_queries_ = on; }
  void set_sync(bool on) { sync_ = on; }
  [[nodiscard]] bool enabled() const { return enabled_; }

  /// Opens/closes the timing of one pass (never nested: GL_TIME_ELAPSED queries cannot nest).
  void begin(std::string_view name);
  void end();

  /// Resolves pending queries and returns one entry per name in first-seen order.
  std::vector<Entry> report();
  /// report() as an aligned text table with a total line.
  std::string table();
  void reset();

 private:
  size_t index_of(std::string_view name);
  struct Pending {
    size_t entry;
    GLuint query;
  };
  bool timer_queries_;
  bool enabled_ = false;
  bool sync_ = false;
  bool open_ = false;
  size_t open_entry_ = 0;
  GLuint open_query_ = 0;
  std::chrono::steady_clock::time_point open_time_;
  std::vector<Entry> entries_;
  std::vector<Pending> pending_;
  std::vector<GLuint> free_queries_;
};

}  // namespace gpgpu
