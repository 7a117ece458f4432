#include "dynamics/embedding.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "math/dual.hpp"
#include "math/multi_dual.hpp"
#include "math/cholesky.hpp"
#include "dynamics/equations.hpp"

namespace kanesens::dynamics {

EmbeddingSets choose_embedding(const Eigen::MatrixXd& A) {
  EmbeddingSets s;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> rows(A.transpose());
  rows.setThreshold(1e-10);
  const Eigen::Index r = rows.rank();
  for (Eigen::Index i = 0; i < r; ++i) s.rows.push_back(static_cast<int>(rows.colsPermutation().indices()[i]));
  std::sort(s.rows.begin(), s.rows.end());
  Eigen::MatrixXd Ar(r, A.cols());
  for (Eigen::Index i = 0; i < r; ++i) Ar.row(i) = A.row(s.rows[static_cast<std::size_t>(i)]);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> cols(Ar);
  std::vector<char> dep(static_cast<std::size_t>(A.cols()), 0);
  for (Eigen::Index i = 0; i < r; ++i) dep[static_cast<std::size_t>(cols.colsPermutation().indices()[i])] = 1;
  for (int k = 0; k < A.cols(); ++k) (dep[static_cast<std::size_t>(k)] ? s.dependent : s.independent).push_back(k);
  return s;
}

double embedding_amplification(const Eigen::MatrixXd& A, const EmbeddingSets& sets) {
  const Eigen::Index nd = static_cast<Eigen::Index>(sets.dependent.size());
  const Eigen::Index ni = static_cast<Eigen::Index>(sets.independent.size());
  Eigen::MatrixXd Ad(nd, nd), Ai(nd, ni);
  for (Eigen::Index a = 0; a < nd; ++a) {
    for (Eigen::Index b = 0; b < nd; ++b) Ad(a, b) = A(sets.rows[static_cast<std::size_t>(a)], sets.dependent[static_cast<std::size_t>(b)]);
    for (Eigen::Index b = 0; b < ni; ++b) Ai(a, b) = A(sets.rows[static_cast<std::size_t>(a)], sets.independent[static_cast<std::size_t>(b)]);
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Ad);
  if (!lu.isInvertible()) return std::numeric_limits<double>::infinity();
  return ni > 0 && nd > 0 ? lu.solve(Ai).cwiseAbs().maxCoeff() : 0.0;
}

template <class S>
EmbeddingScratch<S>::EmbeddingScratch(const Model& m, const EmbeddingSets& sets)
    : dependent_speed(sets.dependent),
      Ad(sets.dependent.size(), sets.dependent.size()),
      pivots(sets.dependent.size()),
      C(m.nu, sets.independent.size()),
      Mt(sets.independent.size(), sets.independent.size()),
      u(m.nu),
      d(m.nu),
      tmp(m.nu),
      r(sets.dependent.size()),
      ft(sets.independent.size()),
      sparsity(m),
      first_row(static_cast<std::size_t>(m.nu)),
      column(static_cast<std::size_t>(m.nu)),
      arranged_rows(sets.rows.size()),
      arranged_dependent(sets.dependent.size()) {
  arrange(sets);
}

template <class S>
void EmbeddingScratch<S>::arrange(const EmbeddingSets& sets) {
  const int nd = static_cast<int>(sets.dependent.size());
  const ConstraintSparsity& sp = sparsity;
  auto at = [](auto& v, int i) -> auto& { return v[static_cast<std::size_t>(i)]; };
  std::fill(first_row.begin(), first_row.end(), nd);  // per speed: the first row of A_d reaching it
  for (int a = nd - 1; a >= 0; --a) {
    const int row = at(sets.rows, a);
    for (int s = at(sp.closure_start, row); s < at(sp.closure_start, row + 1); ++s) at(first_row, at(sp.closure, s)) = a;
  }
  std::copy(sets.dependent.begin(), sets.dependent.end(), dependent_speed.begin());
  std::sort(dependent_speed.begin(), dependent_speed.end(), [&](int k, int l) {  // ties: speed order
    return at(first_row, k) < at(first_row, l) || (at(first_row, k) == at(first_row, l) && k < l);
  });
  std::fill(column.begin(), column.end(), -1);
  for (int b = 0; b < nd; ++b) at(column, at(dependent_speed, b)) = b;
  lower_band = upper_band = 0;
  for (int a = 0; a < nd; ++a) {
    const int row = at(sets.rows, a);
    for (int s = at(sp.closure_start, row); s < at(sp.closure_start, row + 1); ++s) {
      const int b = at(column, at(sp.closure, s));
      if (b < 0) continue;
      lower_band = std::max(lower_band, a - b);
      upper_band = std::max(upper_band, b - a);
    }
  }
  // A column no row reaches makes A_d singular: the full band, as the dense LU.
  for (int b = 0; b < nd; ++b)
    if (at(first_row, at(dependent_speed, b)) == nd) lower_band = upper_band = nd;
  lower_band = std::min(lower_band, std::max(nd - 1, 0));
  upper_band = std::min(upper_band, std::max(nd - 1, 0));
  std::copy(sets.rows.begin(), sets.rows.end(), arranged_rows.begin());
  std::copy(sets.dependent.begin(), sets.dependent.end(), arranged_dependent.begin());
}

namespace {

// Banded LU with partial pivoting (pivots chosen on values) of sc.Ad in place, as LAPACK's gbtrf:
// row interchanges are not applied to earlier multipliers; lu_solve interleaves them.
// Hand-written rather than Eigen's PartialPivLU / SparseLU: it keeps the band, runs on every
// scalar and allocates nothing.
template <class S>
bool factor(EmbeddingScratch<S>& sc) {
  const int n = static_cast<int>(sc.Ad.rows());
  const int kl = sc.lower_band, ku = sc.lower_band + sc.upper_band;
  double big = 0, small = 1e300;
  for (int k = 0; k < n; ++k) {
    const int last_row = std::min(n - 1, k + kl), last_col = std::min(n - 1, k + ku);
    int p = k;
    for (int i = k + 1; i <= last_row; ++i)
      if (std::abs(value_of(sc.Ad(i, k))) > std::abs(value_of(sc.Ad(p, k)))) p = i;
    sc.pivots[k] = p;
    if (p != k)
      for (int j = k; j <= last_col; ++j) std::swap(sc.Ad(k, j), sc.Ad(p, j));
    const double piv = std::abs(value_of(sc.Ad(k, k)));
    big = std::max(big, piv);
    small = std::min(small, piv);
    if (!(piv > 0)) {
      sc.conditioning = std::numeric_limits<double>::infinity();
      return false;
    }
    for (int i = k + 1; i <= last_row; ++i) {
      sc.Ad(i, k) /= sc.Ad(k, k);
      for (int j = k + 1; j <= last_col; ++j) sc.Ad(i, j) -= sc.Ad(i, k) * sc.Ad(k, j);
    }
  }
  sc.conditioning = n > 0 ? big / small : 1;
  return true;
}

// x ← A_d⁻¹ x with the factors of factor().
template <class S>
void lu_solve(const EmbeddingScratch<S>& sc, S* x) {
  const int n = static_cast<int>(sc.Ad.rows());
  const int kl = sc.lower_band, ku = sc.lower_band + sc.upper_band;
  for (int k = 0; k < n; ++k) {
    if (sc.pivots[k] != k) std::swap(x[k], x[sc.pivots[k]]);
    const S xk = x[k];
    for (int i = k + 1; i <= std::min(n - 1, k + kl); ++i) x[i] -= sc.Ad(i, k) * xk;
  }
  for (int i = n - 1; i >= 0; --i) {
    for (int k = i + 1; k <= std::min(n - 1, i + ku); ++k) x[i] -= sc.Ad(i, k) * x[k];
    x[i] /= sc.Ad(i, i);
  }
}

// y = M x with M's structural zeros skipped (the tree's pattern) when it has any.
template <class S>
void mass_times(const Model& m, const Workspace<S>& ws, const S* x, S* y) {
  const int n = m.nu;
  if (ws.mass_matrix_full) {
    for (int k = 0; k < n; ++k) {
      S s = S(0);
      for (int l = 0; l < n; ++l) s += ws.mass_matrix(k, l) * x[l];
      y[k] = s;
    }
    return;
  }
  for (int k = 0; k < n; ++k) y[k] = ws.mass_matrix(k, k) * x[k];
  for (int k = 0; k < n; ++k)
    for (int i = m.speed_parent[k]; i >= 0; i = m.speed_parent[i]) {
      y[k] += ws.mass_matrix(k, i) * x[i];
      y[i] += ws.mass_matrix(i, k) * x[k];
    }
}

}  // namespace

template <class S>
bool reconstruct_speeds(const Model& m, Workspace<S>& ws, EmbeddingScratch<S>& sc, const EmbeddingSets& sets,
                        const S& t, const S* q, const S* ui, S* u) {
  // A and a0 at (q, t): the constraint rows evaluated with u = 0 give A and a0 (= A·0 + a0).
  for (int k = 0; k < m.nu; ++k) sc.tmp[k] = S(0);
  evaluate_constraints(m, ws, t, q, sc.tmp.data());
  const int nd = static_cast<int>(sets.dependent.size());
  if (!sc.arranged_for(sets)) sc.arrange(sets);  // after a repartition
  const int kl = sc.lower_band, ku = kl + sc.upper_band;
  for (int a = 0; a < nd; ++a) {  // the band and the room its fill needs
    const int row = sets.rows[a];
    for (int b = std::max(0, a - kl); b <= std::min(nd - 1, a + ku); ++b)
      sc.Ad(a, b) = ws.constraint_matrix(row, sc.dependent_speed[b]);
  }
  if (!factor(sc)) return false;
  // C = [I; −A_d⁻¹ A_i] and u = C u_i + c.
  for (std::size_t c = 0; c < sets.independent.size(); ++c) {
    for (int k = 0; k < m.nu; ++k) sc.C(k, static_cast<Eigen::Index>(c)) = S(0);
    const int kc = sets.independent[c];
    sc.C(kc, static_cast<Eigen::Index>(c)) = S(1);
    for (int a = 0; a < nd; ++a) sc.r[a] = -ws.constraint_matrix(sets.rows[a], kc);
    lu_solve(sc, sc.r.data());
    for (int a = 0; a < nd; ++a) sc.C(sc.dependent_speed[a], static_cast<Eigen::Index>(c)) = sc.r[a];
  }
  sc.amplification = 0;
  for (std::size_t c = 0; c < sets.independent.size(); ++c)
    for (int a = 0; a < nd; ++a)
      sc.amplification =
          std::max(sc.amplification, std::abs(value_of(sc.C(sc.dependent_speed[a], static_cast<Eigen::Index>(c)))));
  for (int a = 0; a < nd; ++a) sc.r[a] = -ws.velocity_residual[sets.rows[a]];
  lu_solve(sc, sc.r.data());
  for (int k = 0; k < m.nu; ++k) u[k] = S(0);
  for (int a = 0; a < nd; ++a) u[sc.dependent_speed[a]] = sc.r[a];
  for (std::size_t c = 0; c < sets.independent.size(); ++c)
    for (int k = 0; k < m.nu; ++k) u[k] += sc.C(k, static_cast<Eigen::Index>(c)) * ui[c];
  return true;
}

template <class S>
bool embedded_rhs(const Model& m, Workspace<S>& ws, EmbeddingScratch<S>& sc, const EmbeddingSets& sets,
                  const S& t, const S* y, S* ydot, const DynamicsOptions& options) {
  const S* q = y;
  const S* ui = y + m.nq;
  if (!reconstruct_speeds(m, ws, sc, sets, t, q, ui, sc.u.data())) return false;
  const S* u = sc.u.data();
  // reconstruct_speeds left the positions of q evaluated (they depend on q and the parameters
  // only); what depends on u is evaluated again.
  evaluate_state_expressions(m, ws, t, q, u);
  compute_velocity(m, ws, u);
  compute_mass_matrix(m, ws);
  compute_forcing(m, ws, q, u);
  compute_kinematic_derivatives(m, ws, q, u);
  compute_constraints(m, ws, q, u, options);
  const int nd = static_cast<int>(sets.dependent.size());
  const int ni = static_cast<int>(sets.independent.size());
  // d = [0; A_d⁻¹ b]
  for (int a = 0; a < nd; ++a) sc.r[a] = ws.constraint_bias[sets.rows[a]];
  lu_solve(sc, sc.r.data());
  for (int k = 0; k < m.nu; ++k) sc.d[k] = S(0);
  for (int a = 0; a < nd; ++a) sc.d[sc.dependent_speed[a]] = sc.r[a];
  // tmp = f − M d;  f̃ = Cᵀ tmp;  M̃ = Cᵀ M C
  mass_times(m, ws, sc.d.data(), sc.tmp.data());
  for (int k = 0; k < m.nu; ++k) sc.tmp[k] = ws.forcing[k] - sc.tmp[k];
  for (int a = 0; a < ni; ++a) {
    S s = S(0);
    for (int k = 0; k < m.nu; ++k) s += sc.C(k, a) * sc.tmp[k];
    sc.ft[a] = s;
  }
  for (int b = 0; b < ni; ++b) {
    mass_times(m, ws, &sc.C(0, b), sc.tmp.data());  // tmp = M C[:, b]
    for (int a = 0; a <= b; ++a) {
      S s = S(0);
      for (int k = 0; k < m.nu; ++k) s += sc.C(k, a) * sc.tmp[k];
      sc.Mt(a, b) = s;
      sc.Mt(b, a) = s;
    }
  }
  // M̃ u̇_i = f̃ by Cholesky of M̃ in place.
  const std::ptrdiff_t ldm = sc.Mt.outerStride();
  if (!math::cholesky_factor(sc.Mt.data(), ldm, sc.Mt.data(), ldm, ni)) return false;
  S* uid = ydot + m.nq;
  for (int i = 0; i < ni; ++i) uid[i] = sc.ft[i];
  math::cholesky_solve(sc.Mt.data(), ldm, ni, uid);
  for (int i = 0; i < m.nq; ++i) ydot[i] = ws.qdot[i];
  return true;
}

#define KANESENS_INSTANTIATE(S)                                                                              \
  template struct EmbeddingScratch<S>;                                                                       \
  template bool reconstruct_speeds<S>(const Model&, Workspace<S>&, EmbeddingScratch<S>&, const EmbeddingSets&, \
                                      const S&, const S*, const S*, S*);                                       \
  template bool embedded_rhs<S>(const Model&, Workspace<S>&, EmbeddingScratch<S>&, const EmbeddingSets&,       \
                                const S&, const S*, S*, const DynamicsOptions&);
KANESENS_INSTANTIATE(double)
KANESENS_INSTANTIATE(Dual)
KANESENS_FOR_EACH_MULTI_DUAL(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
