#include "sim/solve/output_times.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace kanesens::sim {

namespace {
std::string format(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", t);
  return buf;
}
}  // namespace

void check_output_times(std::span<const double> times, const std::string& who) {
  if (times.empty()) throw std::invalid_argument(who + ": output_times is empty (need at least t0)");
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k]))
      throw std::invalid_argument(who + ": output_times[" + std::to_string(k) + "] is not finite");
    if (k > 0 && !(times[k] > times[k - 1]))
      throw std::invalid_argument(who + ": output_times must be strictly increasing; output_times[" +
                                  std::to_string(k) + "] = " + format(times[k]) + " <= " + format(times[k - 1]));
  }
}

}  // namespace kanesens::sim
