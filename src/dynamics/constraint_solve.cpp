// The augmented solve with Lagrange multipliers (docs/explanation/constraints.md):
//     M u̇ = f + Aᵀλ,   A u̇ = −(Ȧu + ȧ0)  =: b
// solved as u̇ = M⁻¹f + M⁻¹Aᵀλ with (A M⁻¹ Aᵀ) λ = b − A M⁻¹ f.
//
// Dense: A M⁻¹ Aᵀ is formed whole and factored by a pivoted Cholesky; when constraints are
// redundant (rank r < m) λ is the minimum-norm solution.
//
// Sparse (ws.sparse_constraints, M factored along the tree): column j of M⁻¹Aᵀ is solved only
// on T_j and A M⁻¹ Aᵀ is formed and Cholesky-factored only within its envelope
// (ConstraintSparsity). An envelope factor rather than Eigen's SimplicialLDLT: it runs on every
// scalar (dual numbers included) in the workspace without allocating, needs no symbolic
// analysis beyond the envelope, and chains of loops (the common case) number their rows along
// the chain, so the envelope is the band. It does not pivot, so it cannot find a rank: when a
// pivot falls below 1e-8 of the largest diagonal (1000 times the dense path's rank threshold:
// near a singular configuration), that evaluation is done by the dense path, which then decides
// the rank and the minimum-norm λ exactly as it always does.
#include <algorithm>
#include <cmath>

#include "math/cholesky.hpp"
#include "math/dual.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "dynamics/equations.hpp"

namespace kanesens::dynamics {

ConstraintSparsity::ConstraintSparsity(const Model& m) {
  const int n = m.nu, nc = m.nconstraint_rows;
  std::vector<unsigned char> touched(static_cast<std::size_t>(n)), below(static_cast<std::size_t>(n));
  std::vector<std::vector<int>> closures(static_cast<std::size_t>(nc));
  auto mark_body = [&](int b) {
    if (b >= 0)
      for (int k : m.ancestor_speeds[static_cast<std::size_t>(b)]) touched[static_cast<std::size_t>(k)] = 1;
  };
  closure_start.push_back(0);
  support_start.push_back(0);
  for (const Constraint& c : m.constraints) {
    std::fill(touched.begin(), touched.end(), 0);
    switch (c.kind) {
      case Constraint::Kind::coincident:
      case Constraint::Kind::distance:
        mark_body(c.body_a);
        mark_body(c.body_b);
        break;
      case Constraint::Kind::rolling: mark_body(c.body); break;
      case Constraint::Kind::coupler:
        touched[static_cast<std::size_t>(c.speed_a)] = touched[static_cast<std::size_t>(c.speed_b)] = 1;
        break;
      case Constraint::Kind::general:
        if (c.has_position) {
          // The row's entries are ∂g/∂q_k for the coordinates g reads and zero elsewhere.
          for (const auto& [i, k] : c.position_reads) touched[static_cast<std::size_t>(k)] = 1;
        } else {
          for (const auto& [k, a] : c.a) touched[static_cast<std::size_t>(k)] = 1;
        }
        break;
    }
    // Close under speed_parent (children before parents), then T = everything below.
    for (auto it = m.speed_order.rbegin(); it != m.speed_order.rend(); ++it) {
      const int p = m.speed_parent[static_cast<std::size_t>(*it)];
      if (touched[static_cast<std::size_t>(*it)] && p >= 0) touched[static_cast<std::size_t>(p)] = 1;
    }
    for (int k : m.speed_order) {
      const int p = m.speed_parent[static_cast<std::size_t>(k)];
      below[static_cast<std::size_t>(k)] = touched[static_cast<std::size_t>(k)] || (p >= 0 && below[static_cast<std::size_t>(p)]);
    }
    for (int r = 0; r < c.nrows; ++r) {
      std::vector<int> closure_r;
      for (int k : m.speed_order) {
        if (touched[static_cast<std::size_t>(k)]) closure_r.push_back(k);
        if (below[static_cast<std::size_t>(k)]) support.push_back(k);
      }
      closure.insert(closure.end(), closure_r.begin(), closure_r.end());
      closure_start.push_back(static_cast<int>(closure.size()));
      support_start.push_back(static_cast<int>(support.size()));
      closures[static_cast<std::size_t>(c.row_offset + r)] = std::move(closure_r);
    }
  }
  // Envelope: the first earlier row whose closure meets row i's.
  std::vector<int> mark(static_cast<std::size_t>(n), -1);
  envelope_first.assign(static_cast<std::size_t>(nc), 0);
  for (int i = 0; i < nc; ++i) {
    for (int k : closures[static_cast<std::size_t>(i)]) mark[static_cast<std::size_t>(k)] = i;
    int first = i;
    for (int j = 0; j < i && first == i; ++j)
      for (int k : closures[static_cast<std::size_t>(j)])
        if (mark[static_cast<std::size_t>(k)] == i) {
          first = j;
          break;
        }
    envelope_first[static_cast<std::size_t>(i)] = first;
    envelope_entries += static_cast<std::size_t>(i - first + 1);
  }
  support_entries = support.size();
}

namespace {

template <class S>
bool solve_dense(const Model& m, Workspace<S>& ws) {
  using std::sqrt;
  const int n = m.nu, nc = m.nconstraint_rows;
  // M⁻¹ Aᵀ, column by column.
  for (int j = 0; j < nc; ++j) {
    for (int k = 0; k < n; ++k) ws.scratch_nu[k] = ws.constraint_matrix(j, k);
    apply_mass_inverse(m, ws, ws.scratch_nu.data());
    for (int k = 0; k < n; ++k) ws.minv_at(k, j) = ws.scratch_nu[k];
  }
  // Schur complement and right-hand side b − A M⁻¹ f (ws.udot holds M⁻¹ f).
  for (int i = 0; i < nc; ++i) {
    S r = ws.constraint_bias[i];
    for (int k = 0; k < n; ++k) r -= ws.constraint_matrix(i, k) * ws.udot[k];
    ws.schur_rhs[i] = r;
    for (int j = 0; j <= i; ++j) {
      S s = S(0);
      for (int k = 0; k < n; ++k) s += ws.constraint_matrix(i, k) * ws.minv_at(k, j);
      ws.schur(i, j) = s;
      ws.schur(j, i) = s;
    }
  }
  // Pivoted Cholesky P W Pᵀ = L Lᵀ, pivots chosen on values; stops at rank r. (Eigen has no
  // rank-revealing Cholesky: its LDLT pivots but neither stops at the rank nor gives the
  // factor blocks the minimum-norm multipliers below are computed from.)
  auto& W = ws.schur_factor;
  W = ws.schur;
  auto& perm = ws.schur_pivots;
  for (int i = 0; i < nc; ++i) perm[i] = i;
  double max0 = 0;
  for (int i = 0; i < nc; ++i) max0 = std::max(max0, value_of(W(i, i)));
  const double tol = 1e-11 * max0;
  int r = 0;
  for (; r < nc; ++r) {
    int p = r;
    for (int i = r + 1; i < nc; ++i)
      if (value_of(W(i, i)) > value_of(W(p, p))) p = i;
    if (!(value_of(W(p, p)) > tol)) break;
    if (p != r) {
      W.row(r).swap(W.row(p));
      W.col(r).swap(W.col(p));
      std::swap(perm[r], perm[p]);
    }
    W(r, r) = sqrt(W(r, r));
    for (int i = r + 1; i < nc; ++i) W(i, r) /= W(r, r);
    for (int j = r + 1; j < nc; ++j)
      for (int i = j; i < nc; ++i) {
        W(i, j) -= W(i, r) * W(j, r);
        W(j, i) = W(i, j);
      }
  }
  ws.constraint_rank = r;
  // Particular solution in permuted order: [L1⁻ᵀ L1⁻¹ c1; 0].
  auto& lam = ws.scratch_m;
  for (int i = 0; i < nc; ++i) lam[i] = ws.schur_rhs[perm[i]];
  for (int i = 0; i < r; ++i) {
    S s = lam[i];
    for (int k = 0; k < i; ++k) s -= W(i, k) * lam[k];
    lam[i] = s / W(i, i);
  }
  for (int i = r - 1; i >= 0; --i) {
    S s = lam[i];
    for (int k = i + 1; k < r; ++k) s -= W(k, i) * lam[k];
    lam[i] = s / W(i, i);
  }
  for (int i = r; i < nc; ++i) lam[i] = S(0);
  if (r < nc) {
    // Minimum-norm λ: remove the part of λ_p in null(A M⁻¹ Aᵀ), spanned by the columns of
    // N = [−L1⁻ᵀ L2ᵀ; I] (permuted order): λ = λ_p − N (NᵀN)⁻¹ Nᵀ λ_p.
    const int d = nc - r;
    auto& N = ws.nullspace;  // nc × d used
    for (int c = 0; c < d; ++c) {
      for (int i = 0; i < r; ++i) N(i, c) = -W(r + c, i);  // −L2ᵀ column
      for (int i = r - 1; i >= 0; --i) {                     // L1⁻ᵀ
        S s = N(i, c);
        for (int k = i + 1; k < r; ++k) s -= W(k, i) * N(k, c);
        N(i, c) = s / W(i, i);
      }
      for (int i = r; i < nc; ++i) N(i, c) = S(i - r == c ? 1 : 0);
    }
    // Small d×d system (NᵀN) y = Nᵀ λ_p by Cholesky, in the (no longer needed) trailing
    // block of W; NᵀN is positive definite, N having an identity block.
    S* G = &W(r, r);
    const std::ptrdiff_t ldg = W.outerStride();
    for (int b = 0; b < d; ++b)
      for (int a = 0; a <= b; ++a) {  // upper triangle
        S s = S(0);
        for (int i = 0; i < nc; ++i) s += N(i, a) * N(i, b);
        G[b * ldg + a] = s;
      }
    // NᵀN has an identity block, so only a non-finite N (a non-finite system) fails here.
    if (!math::cholesky_factor(G, ldg, G, ldg, d)) return false;
    for (int a = 0; a < d; ++a) {  // y = Nᵀ λ_p, kept in schur_rhs (no longer needed)
      S s = S(0);
      for (int i = 0; i < nc; ++i) s += N(i, a) * lam[i];
      ws.schur_rhs[a] = s;
    }
    math::cholesky_solve(G, ldg, d, ws.schur_rhs.data());
    for (int i = 0; i < nc; ++i)
      for (int a = 0; a < d; ++a) lam[i] -= N(i, a) * ws.schur_rhs[a];
  }
  for (int i = 0; i < nc; ++i) ws.multipliers[perm[i]] = lam[i];
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < nc; ++j) ws.udot[k] += ws.minv_at(k, j) * ws.multipliers[j];
  return r > 0 || nc == 0;
}


// The sparse solve; false when a pivot is too small for an unpivoted factor (the caller then
// uses solve_dense) or the system is not finite.
template <class S>
bool solve_sparse(const Model& m, Workspace<S>& ws) {
  using math::detail::dot;
  using std::sqrt;
  const int nc = m.nconstraint_rows;
  const ConstraintSparsity& sp = ws.constraint_sparsity;
  auto& A = ws.constraint_matrix;
  auto& X = ws.minv_at;
  for (int j = 0; j < nc; ++j) {  // X(:, j) = M⁻¹ a_j on T_j
    const int* T = sp.support.data() + sp.support_start[j];
    const int nt = sp.support_start[j + 1] - sp.support_start[j];
    S* x = &X(0, j);
    for (int s = 0; s < nt; ++s) x[T[s]] = A(j, T[s]);
    apply_mass_inverse(m, ws, x, T, nt);
  }
  // Envelope of A M⁻¹ Aᵀ (upper: column i holds rows envelope_first[i]..i) and b − A M⁻¹ f.
  auto& U = ws.schur_factor;
  double max0 = 0;
  for (int i = 0; i < nc; ++i) {
    S r = ws.constraint_bias[i];
    for (int s = sp.closure_start[i]; s < sp.closure_start[i + 1]; ++s) r -= A(i, sp.closure[s]) * ws.udot[sp.closure[s]];
    ws.schur_rhs[i] = r;
    for (int j = sp.envelope_first[i]; j <= i; ++j) {
      S w = S(0);
      for (int s = sp.support_start[j]; s < sp.support_start[j + 1]; ++s) w += A(i, sp.support[s]) * X(sp.support[s], j);
      U(j, i) = w;
    }
    max0 = std::max(max0, math::value_of(U(i, i)));
  }
  const double tol = 1e-8 * max0;
  for (int i = 0; i < nc; ++i) {  // envelope Cholesky in place, U(j, i) = L(i, j)
    const int fi = sp.envelope_first[i];
    S* Ui = &U(0, i);
    for (int j = fi; j < i; ++j) {
      const int lo = std::max(fi, sp.envelope_first[j]);
      const S* Uj = &U(0, j);
      Ui[j] = (Ui[j] - dot(Uj + lo, Ui + lo, j - lo)) / Uj[j];
    }
    const S d = Ui[i] - dot(Ui + fi, Ui + fi, i - fi);
    if (!(math::value_of(d) > tol)) return false;
    Ui[i] = sqrt(d);
  }
  auto& lam = ws.multipliers;
  for (int i = 0; i < nc; ++i) {  // Uᵀ y = b − A M⁻¹ f
    const int fi = sp.envelope_first[i];
    const S* Ui = &U(0, i);
    lam[i] = (ws.schur_rhs[i] - dot(Ui + fi, lam.data() + fi, i - fi)) / Ui[i];
  }
  for (int i = nc - 1; i >= 0; --i) {  // U λ = y
    const S* Ui = &U(0, i);
    lam[i] /= Ui[i];
    const S li = lam[i];
    for (int k = sp.envelope_first[i]; k < i; ++k) lam[k] -= Ui[k] * li;
  }
  ws.constraint_rank = nc;
  for (int j = 0; j < nc; ++j)
    for (int s = sp.support_start[j]; s < sp.support_start[j + 1]; ++s)
      ws.udot[sp.support[s]] += X(sp.support[s], j) * lam[j];
  return true;
}

}  // namespace

template <class S>
bool solve_constrained_accelerations(const Model& m, Workspace<S>& ws) {
  if (ws.sparse_constraints && solve_sparse(m, ws)) return true;
  return solve_dense(m, ws);
}

#define KANESENS_INSTANTIATE(S) template bool solve_constrained_accelerations<S>(const Model&, Workspace<S>&);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

}  // namespace kanesens::dynamics
