#pragma once
/// \file bench_machine.h
/// The first line of every benchmark's printout: renderer, backend, hardware threads and load
/// average (llvmpipe shares the CPUs with everything else: the figures depend on the load).
#include <fmt/format.h>

#include <fstream>
#include <string>
#include <thread>

#include "gpgpu/gpu.h"

inline void print_machine(gpgpu::Gpu& gpu) {
  std::ifstream loadavg("/proc/loadavg");
  std::string load;
  std::getline(loadavg, load);
  fmt::print("{} ({}), {} hardware threads, LP_NUM_THREADS {}, load average {}\n", gpu.info().renderer,
             gpu.info().backend, std::thread::hardware_concurrency(),
             gpu.info().software_threads.empty() ? "not set" : gpu.info().software_threads,
             load.empty() ? "?" : load.substr(0, load.find(' ', 10)));
}
