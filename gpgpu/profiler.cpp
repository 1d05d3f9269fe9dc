#include "gpgpu/profiler.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "gpgpu/gl_api.h"

namespace gpgpu {

Profiler::~Profiler() {
  for (const Pending& p : pending_) free_queries_.push_back(p.query);
  if (open_) free_queries_.push_back(open_query_);
  if (!free_queries_.empty() && gl::DeleteQueries != nullptr)
    gl::DeleteQueries(static_cast<GLsizei>(free_queries_.size()), free_queries_.data());
}

size_t Profiler::index_of(std::string_view name) {
  for (size_t i = 0; i < entries_.size(); ++i)
    if (entries_[i].name == name) return i;
  entries_.push_back(Entry{std::string(name)});
  if (!timer_queries_) entries_.back().gpu_ms = std::numeric_limits<double>::quiet_NaN();
  return entries_.size() - 1;
}

void Profiler::begin(std::string_view name) {
  if (!enabled_ || open_) return;
  open_ = true;
  open_entry_ = index_of(name);
  if (timer_queries_) {
    if (free_queries_.empty()) {
      GLuint q = 0;
      gl::CreateQueries(GL_TIME_ELAPSED, 1, &q);
      free_queries_.push_back(q);
    }
    open_query_ = free_queries_.back();
    free_queries_.pop_back();
    gl::BeginQuery(GL_TIME_ELAPSED, open_query_);
  }
  open_time_ = std::chrono::steady_clock::now();
}

void Profiler::end() {
  if (!open_) return;
  open_ = false;
  if (timer_queries_) {
    gl::EndQuery(GL_TIME_ELAPSED);
    pending_.push_back({open_entry_, open_query_});
  }
  if (sync_) gl::Finish();
  Entry& e = entries_[open_entry_];
  e.calls += 1;
  e.cpu_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - open_time_).count();
}

std::vector<Profiler::Entry> Profiler::report() {
  for (const Pending& p : pending_) {
    GLuint64 ns = 0;
    gl::GetQueryObjectui64v(p.query, GL_QUERY_RESULT, &ns);
    entries_[p.entry].gpu_ms += static_cast<double>(ns) * 1e-6;
    free_queries_.push_back(p.query);
  }
  pending_.clear();
  return entries_;
}

std::string Profiler::table() {
  const auto entries = report();
  std::string out = fmt::format("{:<32} {:>7} {:>11} {:>11}\n", "pass", "calls", "gpu ms", "cpu ms");
  double gpu = 0, cpu = 0;
  for (const Entry& e : entries) {
    out += fmt::format("{:<32} {:>7} {:>11.3f} {:>11.3f}\n", e.name, e.calls, e.gpu_ms, e.cpu_ms);
    gpu += e.gpu_ms;
    cpu += e.cpu_ms;
  }
  out += fmt::format("{:<32} {:>7} {:>11.3f} {:>11.3f}\n", "total", "", gpu, cpu);
  return out;
}

void Profiler::reset() {
  report();
  entries_.clear();
}

}  // namespace gpgpu
