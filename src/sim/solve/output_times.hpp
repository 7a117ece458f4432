// The output times every integrator takes (CVODES, DOP853, RK4): at least one (output 0 is t0,
// the initial state), finite, strictly increasing. Checked in one place so the three refuse the
// same inputs with the same message.
#pragma once
#include <span>
#include <string>

namespace kanesens::sim {

// Throws std::invalid_argument "<who>: output_times[k] = ... <= output_times[k-1] = ..." etc.
void check_output_times(std::span<const double> times, const std::string& who);

}  // namespace kanesens::sim
