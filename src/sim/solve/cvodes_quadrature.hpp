// CVODES quadratures for an OdeQuadrature (internal to sim/solve): the integrals and their
// forward sensitivities (CVodeQuadInit, CVodeQuadSensInit with the all-at-once fQS), with error
// control at the integration's tolerances. Owned by the Integrator beside its cvode_mem.
#pragma once
#include <vector>

#include "sim/solve/cvodes_callbacks.hpp"
#include "sim/solve/solver_options.hpp"
#include "sim/solve/sundials_handles.hpp"

namespace kanesens::sim::detail {

class CvodesQuadrature {
 public:
  int size() const { return nq_; }
  // After CVodeInit and CVodeSensInit*: nq components, with ns sensitivities each (ns may be 0).
  void build(void* mem, SUNContext ctx, int nq, int ns, const SolverOptions& options, CallbackData& cb);
  // Before each integration: Q(t0) = 0, QS(t0) = 0.
  void reinit(void* mem);
  // At output k: Q and QS at t from CVODES, handed to the quadrature's record().
  void record(void* mem, OdeQuadrature& quadrature, int k, double t);
  // Step-by-step runs: Q and QS interpolated at output time t (≤ the last step's end).
  void record_interpolated(void* mem, OdeQuadrature& quadrature, int k, double t);
  // A restart at t (CVodeReInit): the integrals continue from their values there, which save()
  // takes before the restart and restart() hands to CVODES after it.
  void save(void* mem, double t);
  void restart(void* mem);
  void release() noexcept;

 private:
  int nq_ = 0, ns_ = 0;
  NVectorPtr q_;
  NVectorArray qs_;
  std::vector<const double*> qs_pointers_;
};

}  // namespace kanesens::sim::detail
