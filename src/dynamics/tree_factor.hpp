// The mass matrix of a tree factored along the tree: M = Lᵀ D L with L unit lower triangular in
// the speeds' tree order (Featherstone 2008 §6.5, "LTDL"; MuJoCo's mj_factorM). M_ki is
// structurally zero unless one of k, i is an ancestor of the other (Model::speed_parent), and
// eliminating speeds leaves first keeps that pattern: no fill. Factor and solves cost
// Σ_k depth(k) (for a shallow tree O(nu), for a chain the dense count) and touch nothing else.
//
// Storage: a column-major nu×nu array F; column k holds D_k at row k and L_ki at row i for every
// ancestor i of k (the mass matrix's own entries at those places before factoring). Hand-written
// because the pattern is the tree's (no ordering or symbolic analysis to do) and it must run on
// every scalar without allocation.
//
// A `support` is a list of speeds closed under speed_parent, parents first (Model::speed_order
// is the whole tree). Solving M x = b for b zero outside the speeds' ancestor closure C gives x
// zero outside the descendants of C: a solve restricted to such a support is exact.
#pragma once
#include <cstddef>

#include "math/dual.hpp"
#include "model/model.hpp"

namespace kanesens::dynamics::tree {

// F ← the LᵀDL factor of the ancestor entries of F (in place). False if a pivot D_k is not
// positive (M not positive definite).
template <class S>
bool factor(const model::Model& m, S* F, std::ptrdiff_t ld) {
  const int* parent = m.speed_parent.data();
  for (auto it = m.speed_order.rbegin(); it != m.speed_order.rend(); ++it) {
    const int k = *it;
    S* Fk = F + k * ld;
    const S d = Fk[k];
    if (!(math::value_of(d) > 0)) return false;
    for (int i = parent[k]; i >= 0; i = parent[i]) {
      const S a = Fk[i] / d;
      S* Fi = F + i * ld;
      for (int j = i; j >= 0; j = parent[j]) Fi[j] -= Fk[j] * a;
      Fk[i] = a;
    }
  }
  return true;
}

// x ← M⁻¹ x on `support` (ns speeds, parents first) with the factor F (scalar T: S, or double
// for a multi-tangent x solved with its value factor).
template <class T, class S>
void solve(const model::Model& m, const T* F, std::ptrdiff_t ld, const int* support, int ns, S* x) {
  const int* parent = m.speed_parent.data();
  for (int s = ns - 1; s >= 0; --s) {  // Lᵀ z = x, descendants first
    const int k = support[s];
    const T* Fk = F + k * ld;
    const S xk = x[k];
    for (int i = parent[k]; i >= 0; i = parent[i]) x[i] -= Fk[i] * xk;
  }
  for (int s = 0; s < ns; ++s) {  // D⁻¹, then L x = z, ancestors first
    const int k = support[s];
    const T* Fk = F + k * ld;
    S xk = x[k] / Fk[k];
    for (int i = parent[k]; i >= 0; i = parent[i]) xk -= Fk[i] * x[i];
    x[k] = xk;
  }
}

// F ← M's diagonal and ancestor entries (`value` maps M's scalar to F's).
template <class S, class T, class Value>
void copy_pattern(const model::Model& m, const S* M, std::ptrdiff_t ldm, T* F, std::ptrdiff_t ld, Value value) {
  const int* parent = m.speed_parent.data();
  for (int k : m.speed_order) {
    F[k * ld + k] = value(M[k * ldm + k]);
    for (int i = parent[k]; i >= 0; i = parent[i]) F[k * ld + i] = value(M[k * ldm + i]);
  }
}

}  // namespace kanesens::dynamics::tree
