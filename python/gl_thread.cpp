#include "python/gl_thread.h"

namespace nurbsgl_python {

GlThread& GlThread::instance() {
  // Never destroyed: a joinable std::thread may not be destroyed, and the interpreter's exit may
  // come from any thread, with jobs of other threads still queued.
  static GlThread* gl = new GlThread();
  return *gl;
}

GlThread::GlThread() : thread_([this] { loop(); }) {}

void GlThread::loop() {
  for (;;) {
    std::packaged_task<void()> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return !jobs_.empty(); });
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();  // its exception goes to its future
  }
}

void GlThread::run(const std::function<void()>& job) {
  if (here()) return job();
  std::packaged_task<void()> task(job);
  std::future<void> done = task.get_future();
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(task));
  }
  wake_.notify_one();
  done.get();
}

gpgpu::Gpu& GlThread::gpu() {
  if (!gpu_) {
    gpgpu::ContextOptions options;
    options.backend = gpgpu::backend_from_env();
    gpu_ = std::make_unique<gpgpu::Gpu>(options);
  }
  return *gpu_;
}

}  // namespace nurbsgl_python
