#include "dynamics/embedding.hpp"

#include <Eigen/Dense>
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
    : Ad(sets.dependent.size(), sets.dependent.size()),
      pivots(sets.dependent.size()),
      C(m.nu, sets.independent.size()),
      Mt(sets.independent.size(), sets.independent.size()),
      u(m.nu),
      d(m.nu),
      tmp(m.nu),
      r(sets.dependent.size()),
      ft(sets.independent.size()) {}

namespace {

// LU with partial pivoting (pivots chosen on values) of sc.Ad in place. Hand-written rather than
// Eigen's PartialPivLU: measurably faster on these few-row matrices (`kanesens bench rhs`,
// rhs_embedding), and it allocates nothing.
template <class S>
bool factor(EmbeddingScratch<S>& sc) {
  const int n = static_cast<int>(sc.Ad.rows());
  double big = 0, small = 1e300;
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (std::abs(value_of(sc.Ad(i, k))) > std::abs(value_of(sc.Ad(p, k)))) p = i;
    sc.pivots[k] = p;
    if (p != k) sc.Ad.row(k).swap(sc.Ad.row(p));
    const double piv = std::abs(value_of(sc.Ad(k, k)));
    big = std::max(big, piv);
    small = std::min(small, piv);
    if (!(piv > 0)) {
      sc.conditioning = std::numeric_limits<double>::infinity();
      return false;
    }
    for (int i = k + 1; i < n; ++i) {
      sc.Ad(i, k) /= sc.Ad(k, k);
      for (int j = k + 1; j < n; ++j) sc.Ad(i, j) -= sc.Ad(i, k) * sc.Ad(k, j);
    }
  }
  sc.conditioning = n > 0 ? big / small : 1;
  return true;
}

// x ← A_d⁻¹ x with the factors of factor().
template <class S>
void lu_solve(const EmbeddingScratch<S>& sc, S* x) {
  const int n = static_cast<int>(sc.Ad.rows());
  for (int k = 0; k < n; ++k)
    if (sc.pivots[k] != k) std::swap(x[k], x[sc.pivots[k]]);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < i; ++k) x[i] -= sc.Ad(i, k) * x[k];
  for (int i = n - 1; i >= 0; --i) {
    for (int k = i + 1; k < n; ++k) x[i] -= sc.Ad(i, k) * x[k];
    x[i] /= sc.Ad(i, i);
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
  for (int a = 0; a < nd; ++a) {
    const int row = sets.rows[a];
    for (int b = 0; b < nd; ++b) sc.Ad(a, b) = ws.constraint_matrix(row, sets.dependent[b]);
  }
  if (!factor(sc)) return false;
  // C = [I; −A_d⁻¹ A_i] and u = C u_i + c.
  for (std::size_t c = 0; c < sets.independent.size(); ++c) {
    for (int k = 0; k < m.nu; ++k) sc.C(k, static_cast<Eigen::Index>(c)) = S(0);
    const int kc = sets.independent[c];
    sc.C(kc, static_cast<Eigen::Index>(c)) = S(1);
    for (int a = 0; a < nd; ++a) sc.r[a] = -ws.constraint_matrix(sets.rows[a], kc);
    lu_solve(sc, sc.r.data());
    for (int a = 0; a < nd; ++a) sc.C(sets.dependent[a], static_cast<Eigen::Index>(c)) = sc.r[a];
  }
  sc.amplification = 0;
  for (std::size_t c = 0; c < sets.independent.size(); ++c)
    for (int a = 0; a < nd; ++a)
      sc.amplification =
          std::max(sc.amplification, std::abs(value_of(sc.C(sets.dependent[a], static_cast<Eigen::Index>(c)))));
  for (int a = 0; a < nd; ++a) sc.r[a] = -ws.velocity_residual[sets.rows[a]];
  lu_solve(sc, sc.r.data());
  for (int k = 0; k < m.nu; ++k) u[k] = S(0);
  for (int a = 0; a < nd; ++a) u[sets.dependent[a]] = sc.r[a];
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
  for (int a = 0; a < nd; ++a) sc.d[sets.dependent[a]] = sc.r[a];
  // tmp = f − M d;  f̃ = Cᵀ tmp;  M̃ = Cᵀ M C
  for (int k = 0; k < m.nu; ++k) {
    S s = ws.forcing[k];
    for (int l = 0; l < m.nu; ++l) s -= ws.mass_matrix(k, l) * sc.d[l];
    sc.tmp[k] = s;
  }
  for (int a = 0; a < ni; ++a) {
    S s = S(0);
    for (int k = 0; k < m.nu; ++k) s += sc.C(k, a) * sc.tmp[k];
    sc.ft[a] = s;
  }
  for (int b = 0; b < ni; ++b) {
    for (int k = 0; k < m.nu; ++k) {  // tmp = M C[:, b]
      S s = S(0);
      for (int l = 0; l < m.nu; ++l) s += ws.mass_matrix(k, l) * sc.C(l, b);
      sc.tmp[k] = s;
    }
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
KANESENS_INSTANTIATE(math::MultiDual<4>)
KANESENS_INSTANTIATE(math::MultiDual<8>)
KANESENS_INSTANTIATE(math::MultiDual<12>)
KANESENS_INSTANTIATE(math::MultiDual<16>)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
