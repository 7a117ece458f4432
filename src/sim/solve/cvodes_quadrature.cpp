#include "sim/solve/cvodes_quadrature.hpp"

#include <cvodes/cvodes.h>

#include <exception>
#include <vector>

namespace kanesens::sim::detail {
namespace {

int quadrature_rhs(sunrealtype t, N_Vector y, N_Vector qdot, void* user_data) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "quadrature", t, true, [&] {
    double* f = N_VGetArrayPointer(qdot);
    cb.quadrature->rhs(t, N_VGetArrayPointer(y), f);
    return cb.check_finite("quadrature", t, f, cb.nquad);
  });
}

// All sensitivities at once (CVodeQuadSensInit's form), through pointer arrays sized at build.
int quadrature_sensitivity_rhs(int ns, sunrealtype t, N_Vector y, N_Vector* yS, N_Vector, N_Vector* qsdot,
                               void* user_data, N_Vector, N_Vector) noexcept {
  CallbackData& cb = data_of(user_data);
  return guarded(cb, "quadrature sensitivity", t, true, [&] {
    std::vector<const double*>& s = cb.quadrature_s;
    std::vector<double*>& out = cb.quadrature_sdot;
    for (int i = 0; i < ns; ++i) {
      s[static_cast<std::size_t>(i)] = N_VGetArrayPointer(yS[i]);
      out[static_cast<std::size_t>(i)] = N_VGetArrayPointer(qsdot[i]);
    }
    cb.quadrature->sensitivity_rhs(t, N_VGetArrayPointer(y), ns, s.data(), out.data());
    for (int i = 0; i < ns; ++i) {
      const int flag = cb.check_finite("quadrature sensitivity", t, out[static_cast<std::size_t>(i)], cb.nquad);
      if (flag != 0) return flag;
    }
    return 0;
  });
}

}  // namespace

void CvodesQuadrature::build(void* mem, SUNContext ctx, int nq, int ns, const SolverOptions& o, CallbackData& cb) {
  release();
  cb.quadrature_s.assign(static_cast<std::size_t>(ns), nullptr);
  cb.quadrature_sdot.assign(static_cast<std::size_t>(ns), nullptr);
  nq_ = nq;
  ns_ = ns;
  if (nq == 0) return;
  q_ = make_serial_vector(nq, ctx);
  N_VConst(0.0, q_.get());
  check_flag(CVodeQuadInit(mem, quadrature_rhs, q_.get()), "CVodeQuadInit");
  // The integrals are results: their error is controlled like the states'.
  check_flag(CVodeQuadSStolerances(mem, o.rtol, o.atol), "CVodeQuadSStolerances");
  check_flag(CVodeSetQuadErrCon(mem, SUNTRUE), "CVodeSetQuadErrCon");
  if (ns == 0) return;
  qs_ = NVectorArray(ns, q_.get());
  for (int i = 0; i < ns; ++i) N_VConst(0.0, qs_[i]);
  check_flag(CVodeQuadSensInit(mem, quadrature_sensitivity_rhs, qs_.get()), "CVodeQuadSensInit");
  check_flag(CVodeQuadSensEEtolerances(mem), "CVodeQuadSensEEtolerances");
  check_flag(CVodeSetQuadSensErrCon(mem, o.sens_error_control ? SUNTRUE : SUNFALSE), "CVodeSetQuadSensErrCon");
  qs_pointers_.assign(static_cast<std::size_t>(ns), nullptr);
  for (int i = 0; i < ns; ++i) qs_pointers_[static_cast<std::size_t>(i)] = qs_.data(i);
}

void CvodesQuadrature::reinit(void* mem) {
  if (nq_ == 0) return;
  N_VConst(0.0, q_.get());
  check_flag(CVodeQuadReInit(mem, q_.get()), "CVodeQuadReInit");
  if (ns_ == 0) return;
  for (int i = 0; i < ns_; ++i) N_VConst(0.0, qs_[i]);
  check_flag(CVodeQuadSensReInit(mem, qs_.get()), "CVodeQuadSensReInit");
}

void CvodesQuadrature::record(void* mem, OdeQuadrature& quadrature, int k, double t) {
  if (nq_ == 0) return;
  if (k > 0) {  // output 0 is the initial time: Q = 0 as set by reinit
    double t_reached = t;
    check_flag(CVodeGetQuad(mem, &t_reached, q_.get()), "CVodeGetQuad");
    if (ns_ > 0) check_flag(CVodeGetQuadSens(mem, &t_reached, qs_.get()), "CVodeGetQuadSens");
  }
  quadrature.record(k, t, N_VGetArrayPointer(q_.get()), ns_ > 0 ? qs_pointers_.data() : nullptr);
}

void CvodesQuadrature::record_interpolated(void* mem, OdeQuadrature& quadrature, int k, double t) {
  if (nq_ == 0) return;
  check_flag(CVodeGetQuadDky(mem, t, 0, q_.get()), "CVodeGetQuadDky");
  for (int i = 0; i < ns_; ++i) check_flag(CVodeGetQuadSensDky1(mem, t, 0, i, qs_[i]), "CVodeGetQuadSensDky1");
  quadrature.record(k, t, N_VGetArrayPointer(q_.get()), ns_ > 0 ? qs_pointers_.data() : nullptr);
}

void CvodesQuadrature::save(void* mem, double t) {
  if (nq_ == 0) return;
  check_flag(CVodeGetQuadDky(mem, t, 0, q_.get()), "CVodeGetQuadDky");
  for (int i = 0; i < ns_; ++i) check_flag(CVodeGetQuadSensDky1(mem, t, 0, i, qs_[i]), "CVodeGetQuadSensDky1");
}

void CvodesQuadrature::restart(void* mem) {
  if (nq_ == 0) return;
  check_flag(CVodeQuadReInit(mem, q_.get()), "CVodeQuadReInit");
  if (ns_ > 0) check_flag(CVodeQuadSensReInit(mem, qs_.get()), "CVodeQuadSensReInit");
}

void CvodesQuadrature::release() noexcept {
  qs_ = NVectorArray();
  q_.reset();
  qs_pointers_.clear();
  nq_ = 0;
  ns_ = 0;
}

}  // namespace kanesens::sim::detail
