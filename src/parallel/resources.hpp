// What a run needs of the machine, checked before anything is created: memory per rank for one
// sample's results (the disk check is in ensemble.cpp).
#pragma once
#include <string>

namespace kanesens::parallel {

// Bytes of memory this process may still allocate: the least of MemAvailable (/proc/meminfo),
// the cgroup's memory limit minus its usage, and RLIMIT_AS / RLIMIT_DATA. Infinity when none is
// known. KANESENS_FAULT_MEMORY_AVAILABLE=BYTES replaces it (tests of the check).
double available_memory_bytes();

// "1.5 GiB".
std::string human_bytes(double bytes);

}  // namespace kanesens::parallel
