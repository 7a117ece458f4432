#include "parallel/resources.hpp"

#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

namespace kanesens::parallel {
namespace {

// The first number in `path` (a cgroup or /proc file), or infinity ("max", missing, unreadable).
double read_number(const char* path) {
  std::ifstream in(path);
  double x = 0;
  if (in >> x) return x;
  return std::numeric_limits<double>::infinity();
}

double mem_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024.0;
  return std::numeric_limits<double>::infinity();
}

}  // namespace

double available_memory_bytes() {
  if (const char* fault = std::getenv("KANESENS_FAULT_MEMORY_AVAILABLE")) return std::atof(fault);
  double bytes = mem_available();
  // cgroup v2, then v1: a container or batch job may allow far less than the node has.
  const double v2 = read_number("/sys/fs/cgroup/memory.max") - read_number("/sys/fs/cgroup/memory.current");
  if (v2 == v2) bytes = std::min(bytes, v2);  // inf − inf is NaN: no cgroup limit
  const double v1 = read_number("/sys/fs/cgroup/memory/memory.limit_in_bytes") -
                    read_number("/sys/fs/cgroup/memory/memory.usage_in_bytes");
  if (v1 == v1) bytes = std::min(bytes, v1);
  for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
    struct rlimit limit {};
    if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
      bytes = std::min(bytes, static_cast<double>(limit.rlim_cur));
  }
  return bytes;
}

std::string human_bytes(double b) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (b >= 1024 && u < 6) {
    b /= 1024;
    ++u;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", b, units[u]);
  return buf;
}

}  // namespace kanesens::parallel
