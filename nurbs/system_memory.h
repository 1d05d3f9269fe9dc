#pragma once
/// \file system_memory.h
/// What this machine's memory allows, for refusing a request before the work rather than failing
/// in it (Linux /proc; -1 where unknown).

namespace nurbs {

/// The memory this machine can give a new allocation now (MemAvailable of /proc/meminfo, bytes);
/// -1 when unknown.
[[nodiscard]] long long available_memory();

/// This process's peak resident memory so far (VmHWM of /proc/self/status, bytes); -1 when unknown.
[[nodiscard]] long long peak_resident_memory();

}  // namespace nurbs
