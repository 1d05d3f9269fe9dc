#include "nurbs/system_memory.h"

#include <fstream>
#include <sstream>
#include <string>

namespace nurbs {

long long available_memory() {
  std::ifstream f("/proc/meminfo");
  std::string key, unit;
  long long value = 0;
  while (f >> key >> value >> unit)
    if (key == "MemAvailable:") return unit == "kB" ? value * 1024 : value;
  return -1;
}

long long peak_resident_memory() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream in(line.substr(6));
      long long kb = -1;
      in >> kb;
      return kb < 0 ? -1 : kb * 1024;
    }
  return -1;
}

}  // namespace nurbs
