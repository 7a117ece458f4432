// How the peer programs time one call, the way `kanesens bench rhs` does
// (apps/kanesens/cmd_bench.cpp), so the two sides of a comparison are measured alike: a batch of
// calls long enough (≥ batch_seconds) for the clock to be accurate, calibrated first, then the
// median and minimum time per call over `repeat` batches (the median resists a noisy machine).
// Also how they print an array of numbers in their JSON. Header-only and C++17 (the Simbody
// programs cannot be compiled as C++20).
#pragma once
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace peers {

struct BatchTiming {
  double median_ns = 0, min_ns = 0;
  long long batch = 0;  // calls per batch
  int batches = 0;
};

template <class Call>
BatchTiming time_batches(Call&& call, int repeat, double batch_seconds) {
  using clock = std::chrono::steady_clock;
  auto run = [&](long long k) {
    const auto t0 = clock::now();
    for (long long i = 0; i < k; ++i) call();
    return std::chrono::duration<double>(clock::now() - t0).count();
  };
  long long batch = 1;
  run(batch);  // warm the caches
  while (true) {
    const double s = run(batch);
    if (s >= batch_seconds || batch > (1LL << 40)) break;
    batch = s > 0 ? std::max(2 * batch, static_cast<long long>(1.2 * batch * batch_seconds / s)) : 2 * batch;
  }
  std::vector<double> ns;
  for (int r = 0; r < repeat; ++r) ns.push_back(run(batch) / static_cast<double>(batch) * 1e9);
  std::sort(ns.begin(), ns.end());
  return {ns[ns.size() / 2], ns.front(), batch, repeat};
}

// `  "key": {"median_ns": ..., "min_ns": ..., "evaluations_per_second": ..., "batch": ..., "batches": ...},`
inline void print_timing(const char* key, const BatchTiming& t) {
  std::printf("  \"%s\": {\"median_ns\": %.6g, \"min_ns\": %.6g, \"evaluations_per_second\": %.6g, "
              "\"batch\": %lld, \"batches\": %d},\n",
              key, t.median_ns, t.min_ns, 1e9 / t.median_ns, t.batch, t.batches);
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// `  "name": [x[0], ..., x[n-1]]` and `end`, every number exact (%.17g); x: a pointer or a vector.
template <class Vec>
void print_array(const char* name, const Vec& x, int n, const char* end = ",\n") {
  std::printf("  \"%s\": [", name);
  for (int i = 0; i < n; ++i) std::printf("%s%.17g", i ? ", " : "", static_cast<double>(x[i]));
  std::printf("]%s", end);
}

}  // namespace peers
