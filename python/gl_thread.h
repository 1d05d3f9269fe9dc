#pragma once
/// \file gl_thread.h
/// The Python module's GL context on a thread of its own. A GL context is current on one thread at
/// a time, and Python calls arrive on any thread (a Dask worker runs its tasks on a thread pool):
/// every job that touches GL runs on this one thread, in turn, and the caller waits (the GIL
/// released) for its result or its exception.
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>

#include "gpgpu/gpu.h"

namespace nurbsgl_python {

class GlThread {
 public:
  /// The process's one GL thread, started on first use and never stopped (it waits for work; the
  /// process's exit ends it).
  static GlThread& instance();

  /// Runs `job` on the GL thread and waits; an exception of the job is thrown here.
  void run(const std::function<void()>& job);
  /// Whether the calling thread is the GL thread.
  [[nodiscard]] bool here() const { return std::this_thread::get_id() == thread_.get_id(); }
  /// The context (backend from NURBSGL_GL, else EGL then OSMesa; NURBSGL_EGL_DEVICE picks a device),
  /// started by the first job that asks. On the GL thread only.
  gpgpu::Gpu& gpu();

 private:
  GlThread();
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::packaged_task<void()>> jobs_;
  std::unique_ptr<gpgpu::Gpu> gpu_;
  std::thread thread_;
};

/// A shared_ptr whose object is destroyed on the GL thread (a query holding textures).
template <class T>
std::shared_ptr<T> on_gl_thread(std::unique_ptr<T> object) {
  return std::shared_ptr<T>(object.release(), [](T* p) {
    GlThread& gl = GlThread::instance();
    if (gl.here())
      delete p;
    else
      gl.run([p] { delete p; });
  });
}

}  // namespace nurbsgl_python
