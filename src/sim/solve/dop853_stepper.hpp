// The DOP853 stepper: the stacked state of the solution, its sensitivities and quadratures,
// one step of Dormand and Prince's 8(5,3) pair with its error estimate, and the continuous
// extension of the last accepted step. Internal to sim/solve/dop853.cpp.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstddef>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "sim/solve/dop853.hpp"
#include "sim/solve/dop853_tableau.hpp"

namespace kanesens::sim::dop853_detail {

constexpr int status_too_much_work = -1;  // CV_TOO_MUCH_WORK
constexpr int status_step_too_small = -3;  // CV_ERR_FAILURE
constexpr int status_rhs_failed = -8;      // CV_RHSFUNC_FAIL

constexpr double safety = 0.9, min_factor = 0.2, max_factor = 6.0;
// Step-size control with memory (Hairer's dop853.f BETA; Gustafsson's PI control): the new
// step is h·safety·err^−(1/8 − 0.2β)·err_old^β, err_old the last accepted step's error. β = 0
// (dop853.f's default) rejects many trial steps on oscillating mechanisms;
// β = 0.06 rejects few and needs fewer evaluations at equal accuracy (docs/solve.md).
constexpr double beta = 0.06;
constexpr double error_exponent = -(1.0 / 8.0 - 0.2 * beta);

struct CallbackError {
  std::string what;
};

std::size_t stacked_size(const OdeProblem& problem, int ns, const OdeQuadrature* quad) {
  const std::size_t blocks = 1 + static_cast<std::size_t>(ns);
  return (static_cast<std::size_t>(problem.size()) + (quad ? static_cast<std::size_t>(quad->size()) : 0)) * blocks;
}

// The stacked state z = [y; s_0; ...; s_{ns−1}; Q; QS_0; ...; QS_{ns−1}] (blocks of n, then of
// nq, the quadratures) and everything one step needs, allocated once per integration.
class Stepper {
 public:
  Stepper(OdeProblem& problem, const SolverOptions& o, int ns, OdeQuadrature* quad)
      : z(stacked_size(problem, ns, quad)), z_new(z.size()), problem_(problem), quad_(quad),
        n_(static_cast<std::size_t>(problem.size())), nq_(quad ? static_cast<std::size_t>(quad->size()) : 0), ns_(ns),
        N_(z.size()), stage_(N_), atol_(N_), controlled_(N_), k_(dop853::stages + 1 + dop853::dense_stages, std::vector<double>(N_)),
        rcont_(8, std::vector<double>(N_)) {
    for (std::size_t j = 0; j < n_; ++j) atol_[j] = o.atol_per_state.empty() ? o.atol : o.atol_per_state[j];
    std::fill(controlled_.begin(), controlled_.begin() + static_cast<std::ptrdiff_t>(n_), 1);
    const std::size_t q0 = quadrature_offset();
    for (std::size_t j = 0; j < nq_; ++j) {  // the integrals: error-controlled like the states
      atol_[q0 + j] = o.atol;
      controlled_[q0 + j] = 1;
    }
    std::vector<double> pbar = problem.sensitivity_scales();
    for (int i = 0; i < ns; ++i) {
      const double scale = pbar.empty() ? 1.0 : std::abs(pbar[static_cast<std::size_t>(i)]);
      for (std::size_t j = 0; j < n_ + nq_; ++j) {
        const bool integral = j >= n_;
        const std::size_t r = integral ? q0 + nq_ * (1 + static_cast<std::size_t>(i)) + (j - n_)
                                       : n_ * (1 + static_cast<std::size_t>(i)) + j;
        const double base = integral ? o.atol : atol_[j];
        atol_[r] = o.sens_atol ? *o.sens_atol : base / (scale > 0 ? scale : 1.0);
        controlled_[r] = o.sens_error_control ? 1 : 0;
      }
    }
    n_controlled_ = static_cast<double>(std::count(controlled_.begin(), controlled_.end(), 1));
    rtol_ = o.rtol;
    s_pointers_.resize(static_cast<std::size_t>(ns));
    s_step_.resize(static_cast<std::size_t>(ns));
  }

  std::size_t size() const { return N_; }
  std::size_t states() const { return n_; }
  std::size_t quadrature_offset() const { return n_ * (1 + static_cast<std::size_t>(ns_)); }

  // dz = f(t, z): the ODE, then each sensitivity's right-hand side along it.
  // A RecoverableError leaves dz NaN: the trial step is rejected and retried smaller.
  void f(double t, const std::vector<double>& zz, std::vector<double>& dz, SolverStats& stats) {
    try {
      for (int i = 0; i < ns_; ++i) {
        const std::size_t o = n_ * (1 + static_cast<std::size_t>(i));
        s_in_[static_cast<std::size_t>(i)] = zz.data() + o;
        s_out_[static_cast<std::size_t>(i)] = dz.data() + o;
      }
      problem_.rhs_with_sensitivities(t, zz.data(), ns_, s_in_.data(), dz.data(), s_out_.data());
      ++stats.rhs_evals;
      stats.sens_rhs_evals += ns_;
      if (quad_) {
        const std::size_t q0 = quadrature_offset();
        quad_->rhs(t, zz.data(), dz.data() + q0);
        if (ns_ > 0) {
          for (int i = 0; i < ns_; ++i)
            qs_out_[static_cast<std::size_t>(i)] = dz.data() + q0 + nq_ * (1 + static_cast<std::size_t>(i));
          quad_->sensitivity_rhs(t, zz.data(), ns_, s_in_.data(), qs_out_.data());
        }
      }
    } catch (const RecoverableError& e) {
      std::fill(dz.begin(), dz.end(), std::numeric_limits<double>::quiet_NaN());
      recoverable_message = e.what();
    } catch (const std::exception& e) {
      throw CallbackError{std::string("rhs threw: ") + e.what()};
    }
  }

  // RMS over the controlled components of v / scale, scale = atol + rtol |z| (initial step).
  double norm(const std::vector<double>& v) const {
    double s = 0;
    for (std::size_t j = 0; j < N_; ++j)
      if (controlled_[j]) {
        const double x = v[j] / (atol_[j] + rtol_ * std::abs(z[j]));
        s += x * x;
      }
    return std::sqrt(s / n_controlled_);
  }

  // Hairer's starting step (Solving ODEs I, §II.4): a step whose explicit Euler error would be
  // about 0.01 of the tolerance, refined by a second derivative estimate. k_[0] = f(t, z).
  double initial_step(double t, double h_max, SolverStats& stats) {
    const double d0 = norm(z), d1 = norm(k_[0]);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = std::min(h0, h_max);
    for (std::size_t j = 0; j < N_; ++j) stage_[j] = z[j] + h0 * k_[0][j];
    f(t + h0, stage_, k_[1], stats);
    for (std::size_t j = 0; j < N_; ++j) stage_[j] = k_[1][j] - k_[0][j];
    const double d2 = norm(stage_) / h0;
    const double d = std::max(d1, d2);
    const double h1 = d <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / d, 1.0 / 8.0);
    return std::min({100 * h0, h1, h_max});
  }

  // One trial step of size h from (t, z) with k_[0] = f(t, z): z_new, k_[12] = f(t + h, z_new)
  // and the scaled error (≤ 1: accept). Returns NaN if a stage is not finite.
  double step(double t, double h, SolverStats& stats) {
    for (int i = 1; i < dop853::stages; ++i) {
      combine<Into::state>(dop853::a[i], i, stage_, h);
      f(t + dop853::c[i] * h, stage_, k_[static_cast<std::size_t>(i)], stats);
    }
    combine<Into::sum>(dop853::b, dop853::stages, sum_);
    combine<Into::sum>(dop853::e5, dop853::stages, e5_);
    double e5n = 0, e3n = 0;
    bool finite = true;
    const double *k0 = k_[0].data(), *k8 = k_[8].data(), *k11 = k_[11].data();
    for (std::size_t j = 0; j < N_; ++j) {
      const double s = sum_[j], e5 = e5_[j];
      // e3 = b − bhat3: bhat3 is nonzero in three places only.
      const double e3 = s - (dop853::bhat3_0 * k0[j] + dop853::bhat3_8 * k8[j] + dop853::bhat3_11 * k11[j]);
      z_new[j] = z[j] + h * s;
      finite = finite && std::isfinite(z_new[j]);
      if (!controlled_[j]) continue;
      const double scale = atol_[j] + rtol_ * std::max(std::abs(z[j]), std::abs(z_new[j]));
      e5n += (e5 / scale) * (e5 / scale);
      e3n += (e3 / scale) * (e3 / scale);
    }
    if (!finite) return std::numeric_limits<double>::quiet_NaN();
    f(t + h, z_new, k_[dop853::stages], stats);
    for (double v : k_[dop853::stages])
      if (!std::isfinite(v)) return std::numeric_limits<double>::quiet_NaN();
    const double denominator = e5n + 0.01 * e3n;
    if (!(denominator > 0)) return 0.0;
    return std::abs(h) * e5n / std::sqrt(denominator * n_controlled_);
  }

  // The continuous extension of the accepted trial step from (t, z) to (t + h, z_new), before
  // accept(): Hairer's order-7 dense output (dop853.f, CONTD8), three more evaluations of f.
  // It covers the whole stacked state, so sensitivities and quadratures are interpolated by
  // the same polynomial. Throws CallbackError if an extra stage is not finite (nothing to
  // retry: the step was accepted).
  void prepare_dense(double t, double h, SolverStats& stats) {
    constexpr int S = dop853::stages + 1;  // stages 1..13, the 13th f at the new point
    for (int i = 0; i < dop853::dense_stages; ++i) {
      combine<Into::state>(dop853::a_dense[i], S + i, stage_, h);
      auto& ki = k_[static_cast<std::size_t>(S + i)];
      f(t + dop853::c_dense[i] * h, stage_, ki, stats);
      for (double v : ki)
        if (!std::isfinite(v))
          throw CallbackError{"the dense output's stage is not finite" +
                              (recoverable_message.empty() ? std::string() : ": " + recoverable_message)};
    }
    for (std::size_t j = 0; j < N_; ++j) {
      const double dy = z_new[j] - z[j], bspl = h * k_[0][j] - dy;
      rcont_[0][j] = z[j];
      rcont_[1][j] = dy;
      rcont_[2][j] = bspl;
      rcont_[3][j] = dy - h * k_[dop853::stages][j] - bspl;
    }
    for (int r = 0; r < 4; ++r) {
      auto& c = rcont_[static_cast<std::size_t>(4 + r)];
      combine<Into::scaled>(dop853::d[r], S + dop853::dense_stages, c, h);
    }
    dense_t_ = t;
    dense_h_ = h;
    ++stats.dense_outputs;
  }

  // The continuous extension at time tt in the last prepared step, into out (stacked; the
  // first `count` components only, if given).
  void interpolate(double tt, std::vector<double>& out, std::size_t count = 0) const {
    const double s = (tt - dense_t_) / dense_h_, s1 = 1 - s;
    for (std::size_t j = 0; j < (count ? count : N_); ++j) {
      const auto& c = rcont_;
      out[j] = c[0][j] + s * (c[1][j] + s1 * (c[2][j] + s * (c[3][j] + s1 * (c[4][j] + s * (c[5][j] + s1 * (c[6][j] + s * c[7][j]))))));
    }
  }

  // Accepts the trial step: z = z_new, and its f becomes the next first stage (FSAL).
  void accept() {
    z.swap(z_new);
    k_[0].swap(k_[dop853::stages]);
  }

  // Projects the state block (problem.project) and re-evaluates the first stage if it moved.
  // False if the projection failed.
  bool project(double t, std::vector<double>& corr, SolverStats& stats) {
    const int flag = problem_.project(t, z.data(), corr.data(), 0.0, nullptr);
    ++stats.projections;
    if (flag != 0) return false;
    bool moved = false;
    for (std::size_t j = 0; j < n_; ++j) {
      moved = moved || corr[j] != 0;
      z[j] += corr[j];
    }
    if (moved) f(t, z, k_[0], stats);
    return true;
  }

  // Pointers to the sensitivity blocks of a stacked state zz (the current one by default).
  const double* const* sensitivities(const std::vector<double>* zz = nullptr) {
    const double* base = (zz ? *zz : z).data();
    for (int i = 0; i < ns_; ++i) s_pointers_[static_cast<std::size_t>(i)] = base + n_ * (1 + static_cast<std::size_t>(i));
    return ns_ ? s_pointers_.data() : nullptr;
  }

  // problem.after_step on the current state; if the problem changed its coordinates, the first
  // stage is re-evaluated (a one-step method needs nothing else to restart). True if it did.
  bool after_step(double t, SolverStats& stats) {
    for (int i = 0; i < ns_; ++i) s_step_[static_cast<std::size_t>(i)] = z.data() + n_ * (1 + static_cast<std::size_t>(i));
    bool changed = false;
    try {
      changed = problem_.after_step(t, z.data(), ns_ ? s_step_.data() : nullptr);
    } catch (const std::exception& e) {
      throw CallbackError{e.what()};
    }
    if (!changed) return false;
    ++stats.repartitions;
    f(t, z, k_[0], stats);
    return true;
  }

  // Hands Q and QS at output k to the quadrature's record().
  void record_quadrature(int k, double t, const std::vector<double>* zz = nullptr) {
    if (!quad_) return;
    const double* base = (zz ? *zz : z).data();
    const std::size_t q0 = quadrature_offset();
    for (int i = 0; i < ns_; ++i) qs_pointers_[static_cast<std::size_t>(i)] = base + q0 + nq_ * (1 + static_cast<std::size_t>(i));
    quad_->record(k, t, base + q0, ns_ ? qs_pointers_.data() : nullptr);
  }
  std::vector<double>& first_stage() { return k_[0]; }

 private:
  // out = Σ_l w[l]·k_l over l < count (Into::sum), z + h·Σ (Into::state, a stage's argument)
  // or h·Σ (Into::scaled), summed term by term in the order of l with the tableau's zero
  // weights skipped (they add exact zeros). One pass over the stacked state, a block of
  // `block` components at a time held in registers across the terms: a pass per term, as the
  // rows' sums would be written naively, stores and reloads the sum once per term, and the
  // loop overhead of a short state then costs as much as the arithmetic.
  enum class Into { sum, state, scaled };
  // A block of components as one register (GCC/Clang vector extension, as wide as the build's
  // instruction set allows): written as a loop under the loop over terms, the compiler
  // vectorises across the terms (with gathers) instead.
#if defined(__AVX512F__)
  static constexpr std::size_t block = 8;
#elif defined(__AVX__)
  static constexpr std::size_t block = 4;
#else
  static constexpr std::size_t block = 2;
#endif
  using Block = double __attribute__((vector_size(block * sizeof(double))));
  static Block load(const double* p) {
    Block v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  template <Into into>
  void combine(const double* w, int count, std::vector<double>& out, double h = 1.0) const {
    const double* kl[dop853::stages + 1 + dop853::dense_stages];
    double wl[dop853::stages + 1 + dop853::dense_stages];
    int terms = 0;
    for (int l = 0; l < count; ++l)
      if (w[l] != 0) {
        kl[terms] = k_[static_cast<std::size_t>(l)].data();
        wl[terms++] = w[l];
      }
    double* o = out.data();
    const double* zz = z.data();
    // The row's sum into what `into` asks for, on a component (double) or a block (Block).
    const auto finish = [&](auto sum, auto z_j) {
      if constexpr (into == Into::state) return z_j + h * sum;
      else if constexpr (into == Into::scaled) return sum * h;
      else return sum;
    };
    if (terms == 0) {
      for (std::size_t j = 0; j < N_; ++j) o[j] = finish(0.0, zz[j]);
      return;
    }
    const auto one_block = [&](std::size_t j) {
      Block acc = wl[0] * load(kl[0] + j);
#pragma GCC unroll 1  // unrolled, the sum is kept in memory between the terms
      for (int l = 1; l < terms; ++l) acc += wl[l] * load(kl[l] + j);
      const Block out_j = finish(acc, load(zz + j));
      std::memcpy(o + j, &out_j, sizeof out_j);
    };
    if (N_ >= block) {
      // The last components in a block that overlaps the one before (out is none of the inputs,
      // so they are written again with the same values): a scalar tail costs as much.
      for (std::size_t j = 0; j + block <= N_; j += block) one_block(j);
      if (N_ % block) one_block(N_ - block);
      return;
    }
    for (std::size_t j = 0; j < N_; ++j) {
      double acc = wl[0] * kl[0][j];
      for (int l = 1; l < terms; ++l) acc += wl[l] * kl[l][j];
      o[j] = finish(acc, zz[j]);
    }
  }

 public:
  std::vector<double> z, z_new;  // the current state and the trial step's (stacked)
  std::string recoverable_message;  // the last RecoverableError of the right-hand side

 private:
  OdeProblem& problem_;
  OdeQuadrature* quad_;
  std::size_t n_, nq_;
  int ns_;
  std::size_t N_;
  std::vector<double> stage_, atol_;
  std::vector<double> sum_ = std::vector<double>(N_), e5_ = std::vector<double>(N_);  // step()'s sums
  std::vector<unsigned char> controlled_;
  double n_controlled_ = 1, rtol_ = 0;
  std::vector<std::vector<double>> k_;  // stages 1..13, then the dense output's 14..16
  std::vector<std::vector<double>> rcont_;  // the continuous extension's coefficients
  double dense_t_ = 0, dense_h_ = 1;
  std::vector<const double*> s_pointers_;
  std::vector<const double*> s_in_ = std::vector<const double*>(static_cast<std::size_t>(ns_));  // f's arguments
  std::vector<double*> s_out_ = std::vector<double*>(static_cast<std::size_t>(ns_));
  std::vector<double*> s_step_;
  std::vector<double*> qs_out_ = std::vector<double*>(static_cast<std::size_t>(ns_));  // quadrature call
  std::vector<const double*> qs_pointers_ = std::vector<const double*>(static_cast<std::size_t>(ns_));
};

}  // namespace kanesens::sim::dop853_detail
