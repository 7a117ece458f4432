// Forward dynamics by the articulated-body algorithm (Featherstone 2008 §7.3, table 7.1), on the
// Workspace's frames: each body's quantities at its reference point Q_b with world-aligned axes,
// moved between neighbours by the joint offset r = Q_child − Q_parent (a pure shift), so, as in
// the rest of the dynamics, no large world position enters a difference.
//
// The unknowns are the bodies' accelerations less their bias accelerations (compute_velocity's,
// at u̇ = 0): δa_C = δa_P carried to Q_C + Σ_k s_k u̇_k. The textbook's velocity-product terms are
// then already in the bias, and each body's bias force is p_b = −W_b, its applied minus inertial
// wrench at u̇ = 0 (compute_body_wrenches). Two sweeps of O(1) work per joint (leaves to roots,
// roots to leaves): for a chain this is cheaper than forming M (O(nu²)) and factoring it (O(nu³)).
//
// On every scalar for joints of one speed (several speeds, whose D is factored by Eigen: on
// double only): dual and multi-tangent passes of a chain then cost O(n) like the values.
//
// Inertias are kept as their 21 distinct entries and every product is written in scalars (on
// double, a rotation's step two entries at a time: one_rotation_to_parent): the sweeps are a chain
// of dependent steps, and 6×6 temporaries written by rows and read by columns (or in pieces and
// read in pairs) stall store-to-load forwarding on each of them.
#include <Eigen/Cholesky>

#include "dynamics/equations.hpp"
#include "dynamics/planar_stages.hpp"
#include "math/dual2.hpp"
#include "math/multi_dual.hpp"
#include "math/two_lane.hpp"

namespace kanesens::dynamics {

namespace {
using M6 = Eigen::Matrix<double, 6, 6>;
using V6 = Eigen::Matrix<double, 6, 1>;
template <class S>
using Force6 = std::array<S, 6>;

// Position of (i, j) in the 6-entry storage of a symmetric 3×3 block: the upper triangle by
// columns (00, 01, 11, 02, 12, 22), so that pairs the two-lane step reads sit side by side.
constexpr int kSym[3][3] = {{0, 1, 3}, {1, 2, 4}, {3, 4, 5}};

// Body b's articulated inertia and bias before its joint is swept: its own rigid inertia
// [I h×; −h× m1] and −W_b, plus the sums its children left in its slots (when it has any).
template <class S>
[[gnu::always_inline]] inline void own_plus_children(const SpatialInertia<S>& X, const Vec6<S>& W,
                                                     bool children, const ArticulatedInertiaT<S>& sum,
                                                     const std::array<S, 6>& sum_bias, ArticulatedInertiaT<S>& I,
                                                     S p[6]) {
  const S m = X.m, h0 = X.h[0], h1 = X.h[1], h2 = X.h[2];
  const S a[6] = {X.I(0, 0), X.I(0, 1), X.I(1, 1), X.I(0, 2), X.I(1, 2), X.I(2, 2)};
  if (!children) {
    for (int k = 0; k < 6; ++k) I.A[k] = a[k];
    I.B[0] = S(0), I.B[1] = -h2, I.B[2] = h1;
    I.B[3] = h2, I.B[4] = S(0), I.B[5] = -h0;
    I.B[6] = -h1, I.B[7] = h0, I.B[8] = S(0);
    I.C[0] = I.C[2] = I.C[5] = m;
    I.C[1] = I.C[3] = I.C[4] = S(0);
    for (int k = 0; k < 6; ++k) p[k] = -W[k];
    return;
  }
  for (int k = 0; k < 6; ++k) I.A[k] = sum.A[k] + a[k];
  I.B[0] = sum.B[0], I.B[1] = sum.B[1] - h2, I.B[2] = sum.B[2] + h1;
  I.B[3] = sum.B[3] + h2, I.B[4] = sum.B[4], I.B[5] = sum.B[5] - h0;
  I.B[6] = sum.B[6] - h1, I.B[7] = sum.B[7] + h0, I.B[8] = sum.B[8];
  I.C[0] = sum.C[0] + m, I.C[1] = sum.C[1], I.C[2] = sum.C[2] + m;
  I.C[3] = sum.C[3], I.C[4] = sum.C[4], I.C[5] = sum.C[5] + m;
  for (int k = 0; k < 6; ++k) p[k] = sum_bias[k] - W[k];
}

// A child's share of its parent's slots: the first child swept writes them, the others add.
template <bool first, class S>
[[gnu::always_inline]] inline void put(S& slot, const S& share) {
  if constexpr (first) slot = share;
  else slot += share;
}

void to_matrix(const ArticulatedInertia& I, M6& M) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      M(i, j) = I.A[kSym[i][j]];
      M(i, 3 + j) = I.B[3 * i + j];
      M(3 + j, i) = I.B[3 * i + j];
      M(3 + i, 3 + j) = I.C[kSym[i][j]];
    }
}

void from_matrix(const M6& M, ArticulatedInertia& I) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (j >= i) I.A[kSym[i][j]] = 0.5 * (M(i, j) + M(j, i));
      if (j >= i) I.C[kSym[i][j]] = 0.5 * (M(3 + i, 3 + j) + M(3 + j, 3 + i));
      I.B[3 * i + j] = 0.5 * (M(i, 3 + j) + M(3 + j, i));
    }
}

// Xᵀ I X, X the shift of motion vectors from Q_P to Q_C = Q_P + r: an articulated inertia at the
// child's point seen from the parent's. With R = r×: A' = A − B R − (B R)ᵀ − R C R, B' = B + R C,
// C' = C. Since R C R is symmetric, A' = A − K R − (K R)ᵀ with K = B + H, H = ½ R C, and
// B' = K + H: 39 multiplications instead of 48 (row i of K R is k_i × r, column j of R C is
// r × c_j).
template <class S>
[[gnu::always_inline]] inline ArticulatedInertiaT<S> shifted_to_parent(const ArticulatedInertiaT<S>& I,
                                                                       const S r[3]) {
  const S r0 = r[0], r1 = r[1], r2 = r[2];
  const S q0 = S(0.5) * r0, q1 = S(0.5) * r1, q2 = S(0.5) * r2;
  ArticulatedInertiaT<S> out;
  S K[3][3];
  for (int j = 0; j < 3; ++j) {
    const S c0 = I.C[kSym[0][j]], c1 = I.C[kSym[1][j]], c2 = I.C[kSym[2][j]];
    const S H[3] = {q1 * c2 - q2 * c1, q2 * c0 - q0 * c2, q0 * c1 - q1 * c0};
    for (int i = 0; i < 3; ++i) {
      K[i][j] = I.B[3 * i + j] + H[i];
      out.B[3 * i + j] = K[i][j] + H[i];
    }
  }
  S KR[3][3];
  for (int i = 0; i < 3; ++i) {
    KR[i][0] = K[i][1] * r2 - K[i][2] * r1;
    KR[i][1] = K[i][2] * r0 - K[i][0] * r2;
    KR[i][2] = K[i][0] * r1 - K[i][1] * r0;
  }
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) out.A[kSym[i][j]] = I.A[kSym[i][j]] - (KR[i][j] + KR[j][i]);
  for (int k = 0; k < 6; ++k) out.C[k] = I.C[k];
  return out;
}

template <bool first, class S>
void add_to(const ArticulatedInertiaT<S>& X, ArticulatedInertiaT<S>& parent) {
  for (int k = 0; k < 6; ++k) put<first>(parent.A[k], X.A[k]);
  for (int k = 0; k < 9; ++k) put<first>(parent.B[k], X.B[k]);
  for (int k = 0; k < 6; ++k) put<first>(parent.C[k], X.C[k]);
}

// (n, f) at Q_C as a force at Q_P = Q_C − r: (n + r × f, f).
template <class S>
[[gnu::always_inline]] inline Force6<S> force_to_parent(const S f[6], const S r[3]) {
  return {f[0] + (r[1] * f[5] - r[2] * f[4]), f[1] + (r[2] * f[3] - r[0] * f[5]),
          f[2] + (r[0] * f[4] - r[1] * f[3]), f[3], f[4], f[5]};
}

// A joint of one speed s = (a, 0) or (0, a) with articulated inertia I and bias p at the child:
// U = I s, D = sᵀ U, u = τ − sᵀ p. Adds the child's contribution to its parent,
// Xᵀ (I − U Uᵀ/D) X and Xᵀ (p + U u/D), as Xᵀ I X − U' U'ᵀ/D and Xᵀ p + U' u/D with U' = Xᵀ U
// (one rank-one update, at the parent's point). Stores W = U'/D and u/D, from which the forward
// sweep gets u̇ = u/D − Wᵀ δa_P (δa_P at the parent's point, since U'ᵀ δa_P = Uᵀ X δa_P).
// Returns false unless D > 0.
template <bool first, class S>
bool one_speed_to_parent(const ArticulatedInertiaT<S>& I, const S p[6], const S a[3], bool rotation, const S& tau,
                         const S r[3], bool has_parent, ArticulatedInertiaT<S>* parent, S* parent_bias, S W[6],
                         S& u_over_d) {
  const S a0 = a[0], a1 = a[1], a2 = a[2];
  S U[6];
  S d, u;
  if (rotation) {  // U = (A a, Bᵀ a)
    for (int i = 0; i < 3; ++i) U[i] = I.A[kSym[i][0]] * a0 + I.A[kSym[i][1]] * a1 + I.A[kSym[i][2]] * a2;
    for (int i = 0; i < 3; ++i) U[3 + i] = I.B[i] * a0 + I.B[3 + i] * a1 + I.B[6 + i] * a2;
    d = a0 * U[0] + a1 * U[1] + a2 * U[2];
    u = tau - (a0 * p[0] + a1 * p[1] + a2 * p[2]);
  } else {  // U = (B a, C a)
    for (int i = 0; i < 3; ++i) U[i] = I.B[3 * i] * a0 + I.B[3 * i + 1] * a1 + I.B[3 * i + 2] * a2;
    for (int i = 0; i < 3; ++i) U[3 + i] = I.C[kSym[i][0]] * a0 + I.C[kSym[i][1]] * a1 + I.C[kSym[i][2]] * a2;
    d = a0 * U[3] + a1 * U[4] + a2 * U[5];
    u = tau - (a0 * p[3] + a1 * p[4] + a2 * p[5]);
  }
  if (!(math::value_of(d) > 0)) return false;
  const S dinv = S(1.0) / d;
  u_over_d = u * dinv;
  const Force6<S> Up = has_parent ? force_to_parent<S>(U, r) : Force6<S>{U[0], U[1], U[2], U[3], U[4], U[5]};
  for (int i = 0; i < 6; ++i) W[i] = Up[i] * dinv;
  if (!has_parent) return true;
  const ArticulatedInertiaT<S> X = shifted_to_parent(I, r);
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      put<first>(parent->A[kSym[i][j]], X.A[kSym[i][j]] - Up[i] * W[j]);
      put<first>(parent->C[kSym[i][j]], X.C[kSym[i][j]] - Up[3 + i] * W[3 + j]);
    }
    for (int j = 0; j < 3; ++j) put<first>(parent->B[3 * i + j], X.B[3 * i + j] - Up[i] * W[3 + j]);
  }
  const Force6<S> pp = force_to_parent<S>(p, r);
  for (int i = 0; i < 6; ++i) put<first>(parent_bias[i], pp[i] + Up[i] * u_over_d);
  return true;
}

#if defined(__SSE2__)
// The step for a rotation s = (a, 0) on double, two entries per instruction: own_plus_children
// and one_speed_to_parent in one, with the body's articulated inertia kept in registers. Every
// entry is formed by the same operations in the same order as there, so the values are the same
// bits (x − 0 and x − (−h) stand for the scalar form's x and x + h, bit for bit). The pairs follow
// the storage (kSym, B by rows) so that operands load side by side and each child's stores are
// read back as the same pieces by its parent. Written by hand because the compiler's code for the
// scalar form spends more instructions moving the 21 entries through registers and the stack than
// computing them.
template <bool first>
bool one_rotation_to_parent(const SpatialInertia<double>& X, const Vec6<double>& wrench,
                            bool children, const ArticulatedInertia& sum,
                            const std::array<double, 6>& sum_bias, const double a[3], double tau,
                            const double r[3], bool has_parent, ArticulatedInertia* parent,
                            double* parent_bias, double W[6], double& u_over_d) {
  using namespace math::two_lane;
  // The body's articulated inertia I: A as (A00, A01), (A02, A12), A11, A22; B by rows (Bi0, Bi1)
  // and Bi2; C as A. Its bias p = sum_bias − W_b.
  const double* Xi = X.I.data();  // column-major
  const double m = X.m, h0 = X.h[0], h1 = X.h[1], h2 = X.h[2];
  V2 A01 = pair(Xi[0], Xi[3]), A0212 = load(Xi + 6);
  double A11 = Xi[4], A22 = Xi[8];
  V2 B0, B1, B2, C01, C0212;
  double B02, B12, B22, C11, C22;
  V2 p01, p34;
  double p2, p5;
  const double* w = wrench.data();
  if (children) {
    A01 = add(load(sum.A), A01), A0212 = add(load(sum.A + 3), A0212);
    A11 = sum.A[2] + A11, A22 = sum.A[5] + A22;
    B0 = sub(load(sum.B), pair(0.0, h2)), B02 = sum.B[2] + h1;
    B1 = sub(load(sum.B + 3), pair(-h2, 0.0)), B12 = sum.B[5] - h0;
    B2 = sub(load(sum.B + 6), pair(h1, -h0)), B22 = sum.B[8];
    C01 = sub(load(sum.C), pair(-m, 0.0)), C11 = sum.C[2] + m;
    C0212 = load(sum.C + 3), C22 = sum.C[5] + m;
    p01 = sub(load(sum_bias.data()), load(w)), p2 = sum_bias[2] - w[2];
    p34 = sub(load(sum_bias.data() + 3), load(w + 3)), p5 = sum_bias[5] - w[5];
  } else {
    B0 = pair(0.0, -h2), B02 = h1;
    B1 = pair(h2, 0.0), B12 = -h0;
    B2 = pair(-h1, h0), B22 = 0.0;
    C01 = pair(m, 0.0), C11 = m;
    C0212 = zero(), C22 = m;
    p01 = negate(load(w)), p2 = -w[2];
    p34 = negate(load(w + 3)), p5 = -w[5];
  }
  const double a0 = a[0], a1 = a[1], a2 = a[2];
  const V2 Va0 = splat(a0), Va1 = splat(a1), Va2 = splat(a2);
  // U = I s = (A a, Bᵀ a) as (U0, U1), (U3, U4) and (U2, U5).
  const V2 U01 = add(add(mul(A01, Va0), mul(high_low(A01, low(A11)), Va1)), mul(A0212, Va2));
  const V2 U34 = add(add(mul(B0, Va0), mul(B1, Va1)), mul(B2, Va2));
  const V2 U25 = add(add(mul(lows(A0212, low(B02)), Va0), mul(high_low(A0212, low(B12)), Va1)),
                     mul(pair(A22, B22), Va2));
  const double U0 = lo(U01), U1 = hi(U01), U2 = lo(U25), U3 = lo(U34), U4 = hi(U34), U5 = hi(U25);
  const double d = a0 * U0 + a1 * U1 + a2 * U2;
  const double u = tau - (a0 * lo(p01) + a1 * hi(p01) + a2 * p2);
  if (!(d > 0)) return false;
  const double dinv = 1.0 / d;
  u_over_d = u * dinv;
  const V2 Dinv = splat(dinv);
  if (!has_parent) {
    store(W, mul(U01, Dinv));
    W[2] = U2 * dinv;
    store(W + 3, mul(U34, Dinv));
    W[5] = U5 * dinv;
    return true;
  }
  const double r0 = r[0], r1 = r[1], r2 = r[2];
  // U' = Xᵀ U = (U_top + r × U_bot, U_bot), W = U'/D.
  const double Up0 = U0 + (r1 * U5 - r2 * U4), Up1 = U1 + (r2 * U3 - r0 * U5),
               Up2 = U2 + (r0 * U4 - r1 * U3);
  const V2 Up01 = pair(Up0, Up1);
  const V2 W01 = mul(Up01, Dinv), W34 = mul(U34, Dinv);
  const double W2 = Up2 * dinv, W5 = U5 * dinv;
  store(W, W01);
  W[2] = W2;
  store(W + 3, W34);
  W[5] = W5;
  // C' = C − U'_bot W_botᵀ.
  put_pair<first>(parent->C, sub(C01, mul(splat(U3), W34)));
  put<first>(parent->C[2], C11 - U4 * hi(W34));
  put_pair<first>(parent->C + 3, sub(C0212, mul(U34, splat(W5))));
  put<first>(parent->C[5], C22 - U5 * W5);
  // H = ½ R C (rows in pairs over columns 0 and 1; column 2 alone), K = B + H,
  // B' = K + H − U'_top W_botᵀ.
  const double q0 = 0.5 * r0, q1 = 0.5 * r1, q2 = 0.5 * r2;
  const V2 Q0 = splat(q0), Q1 = splat(q1), Q2 = splat(q2);
  const V2 C12 = high_low(C01, low(C11));  // (C01, C11)
  const double C02 = lo(C0212), C12s = hi(C0212);
  const V2 H0 = sub(mul(Q1, C0212), mul(Q2, C12));
  const V2 H1 = sub(mul(Q2, C01), mul(Q0, C0212));
  const V2 H2 = sub(mul(Q0, C12), mul(Q1, C01));
  const double H02 = q1 * C22 - q2 * C12s, H12 = q2 * C02 - q0 * C22, H22 = q0 * C12s - q1 * C02;
  const V2 K0 = add(B0, H0), K1 = add(B1, H1), K2 = add(B2, H2);
  const double K02 = B02 + H02, K12 = B12 + H12, K22 = B22 + H22;
  put_pair<first>(parent->B, sub(add(K0, H0), mul(splat(Up0), W34)));
  put<first>(parent->B[2], (K02 + H02) - Up0 * W5);
  put_pair<first>(parent->B + 3, sub(add(K1, H1), mul(splat(Up1), W34)));
  put<first>(parent->B[5], (K12 + H12) - Up1 * W5);
  put_pair<first>(parent->B + 6, sub(add(K2, H2), mul(splat(Up2), W34)));
  put<first>(parent->B[8], (K22 + H22) - Up2 * W5);
  // K R by columns (rows 0 and 1 in pairs; row 2 alone), A' = A − (K R + (K R)ᵀ) − U'_top W_topᵀ.
  const V2 R0 = splat(r0), R1 = splat(r1), R2 = splat(r2);
  const V2 Kc0 = lows(K0, K1), Kc1 = highs(K0, K1), Kc2 = pair(K02, K12);
  const V2 KR0 = sub(mul(Kc1, R2), mul(Kc2, R1));  // (KR00, KR10)
  const V2 KR1 = sub(mul(Kc2, R0), mul(Kc0, R2));  // (KR01, KR11)
  const V2 KR2 = sub(mul(Kc0, R1), mul(Kc1, R0));  // (KR02, KR12)
  const double K20 = lo(K2), K21 = hi(K2);
  const double KR20 = K21 * r2 - K22 * r1, KR21 = K22 * r0 - K20 * r2, KR22 = K20 * r1 - K21 * r0;
  const double KR11 = hi(KR1);
  put_pair<first>(parent->A, sub(sub(A01, add(lows(KR0, KR1), KR0)), mul(splat(Up0), W01)));
  put<first>(parent->A[2], (A11 - (KR11 + KR11)) - Up1 * hi(W01));
  put_pair<first>(parent->A + 3, sub(sub(A0212, add(KR2, pair(KR20, KR21))), mul(Up01, splat(W2))));
  put<first>(parent->A[5], (A22 - (KR22 + KR22)) - Up2 * W2);
  // Xᵀ p + U' u/D.
  const double p0 = lo(p01), p1 = hi(p01), p3 = lo(p34), p4 = hi(p34);
  const V2 UD = splat(u_over_d);
  put_pair<first>(parent_bias,
                  add(pair(p0 + (r1 * p5 - r2 * p4), p1 + (r2 * p3 - r0 * p5)), mul(Up01, UD)));
  put<first>(parent_bias[2], (p2 + (r0 * p4 - r1 * p3)) + Up2 * u_over_d);
  put_pair<first>(parent_bias + 3, add(p34, mul(U34, UD)));
  put<first>(parent_bias[5], p5 + U5 * u_over_d);
  return true;
}
#endif

// A joint of several speeds (spherical, free, universal, …): U = I S, D = Sᵀ U (factored),
// u = τ − Sᵀ p, and the child's I − U D⁻¹ Uᵀ, p + U D⁻¹ u in place, to be added to the parent.
// Leaves U in `columns` and D⁻¹ in Dinv, and u in x. Returns false unless D is positive definite.
bool project_speeds(ArticulatedInertia& I, double p[6], const Vec6<double>* s, const unsigned char* rotation, int n,
                    const double* tau, bool has_parent, V6* columns, M6& Dinv, double* x) {
  M6 IA;
  to_matrix(I, IA);
  for (int c = 0; c < n; ++c) {  // s = (a, 0) or (0, a): half of I^A and of p^A
    if (rotation[c]) {
      columns[c].noalias() = IA.leftCols<3>() * s[c].head<3>();
      x[c] = tau[c] - (s[c][0] * p[0] + s[c][1] * p[1] + s[c][2] * p[2]);
    } else {
      columns[c].noalias() = IA.rightCols<3>() * s[c].tail<3>();
      x[c] = tau[c] - (s[c][3] * p[3] + s[c][4] * p[4] + s[c][5] * p[5]);
    }
  }
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> D(n, n);
  for (int c = 0; c < n; ++c)
    for (int d = 0; d < n; ++d) D(c, d) = s[c].dot(columns[d]);
  const Eigen::LLT<decltype(D)> llt(D);
  if (llt.info() != Eigen::Success) return false;
  Dinv.topLeftCorner(n, n) = llt.solve(decltype(D)::Identity(n, n));
  if (!has_parent) return true;
  for (int c = 0; c < n; ++c) {
    V6 w = columns[0] * Dinv(0, c);  // column c of U D⁻¹
    for (int d = 1; d < n; ++d) w += columns[d] * Dinv(d, c);
    IA.noalias() -= w * columns[c].transpose();
    for (int i = 0; i < 6; ++i) p[i] += w[i] * x[c];
  }
  from_matrix(IA, I);
  return true;
}
}  // namespace

template <class S>
bool articulated_body_accelerations(const Model& m, Workspace<S>& ws) {
  S* x = ws.udot.data();  // u/D (one speed) or u = τ − Sᵀ p^A (several) on the way in, u̇ out
  // Leaves to roots: I^A, p^A of each body's subtree; each child's share goes to its parent's
  // slots (Workspace::articulated_first).
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    const int n = J.nu, k0 = J.u_offset, C = J.child;
#if defined(__SSE2__)
    if constexpr (std::is_same_v<S, double>) {
      if (n == 1 && m.speed_rotation[k0]) {
        const bool has_parent = J.parent >= 0, first = ws.articulated_first[*it] != 0;
        const bool children = ws.articulated_has_children[C] != 0;
        ArticulatedInertia* parent = has_parent ? &ws.articulated_inertia[J.parent] : nullptr;
        double* parent_bias = has_parent ? ws.articulated_bias[J.parent].data() : nullptr;
        const double* r = ws.joint_offset[*it].data();
        const double* s = ws.partial[k0].data();
        double* W = ws.articulated_columns[k0].data();
        const bool ok = first ? one_rotation_to_parent<true>(
                                    ws.spatial_inertia[C], ws.wrench[C], children,
                                    ws.articulated_inertia[C], ws.articulated_bias[C], s,
                                    ws.forcing[k0], r, has_parent, parent, parent_bias, W, x[k0])
                              : one_rotation_to_parent<false>(
                                    ws.spatial_inertia[C], ws.wrench[C], children,
                                    ws.articulated_inertia[C], ws.articulated_bias[C], s,
                                    ws.forcing[k0], r, has_parent, parent, parent_bias, W, x[k0]);
        if (!ok) return false;
        continue;
      }
    }
#endif
    ArticulatedInertiaT<S> IA;
    S pA[6];
    own_plus_children(ws.spatial_inertia[C], ws.wrench[C], ws.articulated_has_children[C] != 0,
                      ws.articulated_inertia[C], ws.articulated_bias[C], IA, pA);
    const S* r = ws.joint_offset[*it].data();
    const bool has_parent = J.parent >= 0, first = ws.articulated_first[*it] != 0;
    if (n == 1) {
      const Vec6<S>& s = ws.partial[k0];
      const bool rotation = m.speed_rotation[k0] != 0;
      const S* a = rotation ? s.data() : s.data() + 3;
      ArticulatedInertiaT<S>* parent = has_parent ? &ws.articulated_inertia[J.parent] : nullptr;
      S* parent_bias = has_parent ? ws.articulated_bias[J.parent].data() : nullptr;
      S* W = ws.articulated_columns[k0].data();
      if (!(first ? one_speed_to_parent<true>(IA, pA, a, rotation, ws.forcing[k0], r, has_parent, parent, parent_bias,
                                              W, x[k0])
                  : one_speed_to_parent<false>(IA, pA, a, rotation, ws.forcing[k0], r, has_parent, parent,
                                               parent_bias, W, x[k0])))
        return false;
      continue;
    }
    if constexpr (!std::is_same_v<S, double>) {
      if (n > 1) return false;  // several speeds: on double only (set_articulated_body)
    } else if (n > 1) {
      V6 U[6];
      if (!project_speeds(IA, pA, ws.partial.data() + k0, m.speed_rotation.data() + k0, n, ws.forcing.data() + k0,
                          has_parent, U, ws.joint_inverse[*it], x + k0))
        return false;
      for (int c = 0; c < n; ++c)
        for (int i = 0; i < 6; ++i) ws.articulated_columns[k0 + c][i] = U[c][i];
    }
    if (has_parent) {
      const ArticulatedInertiaT<S> X = shifted_to_parent(IA, r);
      const Force6<S> pp = force_to_parent<S>(pA, r);
      S* parent_bias = ws.articulated_bias[J.parent].data();
      if (first) {
        add_to<true>(X, ws.articulated_inertia[J.parent]);
        for (int i = 0; i < 6; ++i) parent_bias[i] = pp[i];
      } else {
        add_to<false>(X, ws.articulated_inertia[J.parent]);
        for (int i = 0; i < 6; ++i) parent_bias[i] += pp[i];
      }
    }
  }
  // Roots to leaves: δa_C = X δa_P + S u̇, with u̇ = u/D − Wᵀ δa_P (one speed) or
  // D⁻¹ (u − Uᵀ X δa_P) (several). A body's p^A is not needed once its joint is done, so its slot
  // holds δa. Along a chain the parent's δa is the one just formed: it is carried in scalars
  // (reading back what was just stored, in pairs, would stall store-to-load forwarding).
  S a0 = S(0), a1 = S(0), a2 = S(0), a3 = S(0), a4 = S(0), a5 = S(0);
  int carried = -1;  // the body whose δa a0…a5 hold
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int n = J.nu, k0 = J.u_offset;
    if (J.parent < 0) {
      a0 = a1 = a2 = a3 = a4 = a5 = S(0);
    } else if (J.parent != carried) {
      const std::array<S, 6>& P = ws.articulated_bias[J.parent];
      a0 = P[0], a1 = P[1], a2 = P[2], a3 = P[3], a4 = P[4], a5 = P[5];
    }
    // Here a = δa_P; u̇ of a one-speed joint needs it at the parent's point.
    S ud = S(0);
    if (n == 1) {
      const std::array<S, 6>& W = ws.articulated_columns[k0];
      // Summed as a tree with the translational half of δa_P apart: along a chain of rotations it
      // is known a joint earlier than the rotational half, so u̇ waits on fewer additions.
      const S late = W[0] * a0 + W[1] * a1, early = W[2] * a2 + (W[3] * a3 + W[4] * a4 + W[5] * a5);
      ud = x[k0] - (late + early);
      x[k0] = ud;
    }
    if (J.parent >= 0) {  // δa_P at Q_C
      const S* r = ws.joint_offset[ji].data();
      const S b3 = a3 + (a1 * r[2] - a2 * r[1]), b4 = a4 + (a2 * r[0] - a0 * r[2]), b5 = a5 + (a0 * r[1] - a1 * r[0]);
      a3 = b3, a4 = b4, a5 = b5;
    }
    if (n == 1) {
      const S* s = ws.partial[k0].data();
      if (m.speed_rotation[k0]) {
        a0 += s[0] * ud, a1 += s[1] * ud, a2 += s[2] * ud;
      } else {
        a3 += s[3] * ud, a4 += s[4] * ud, a5 += s[5] * ud;
      }
    } else if (n > 1) {
      if constexpr (std::is_same_v<S, double>) {  // several speeds: on double only (set_articulated_body)
      const double a[6] = {a0, a1, a2, a3, a4, a5};
      double rr[6];
      for (int c = 0; c < n; ++c) {
        const std::array<double, 6>& U = ws.articulated_columns[k0 + c];
        rr[c] = x[k0 + c] - (U[0] * a[0] + U[1] * a[1] + U[2] * a[2] + U[3] * a[3] + U[4] * a[4] + U[5] * a[5]);
      }
      const M6& Dinv = ws.joint_inverse[ji];
      for (int c = 0; c < n; ++c) {
        double v = 0;
        for (int d = 0; d < n; ++d) v += Dinv(c, d) * rr[d];
        x[k0 + c] = v;
        const double* s = ws.partial[k0 + c].data();
        if (m.speed_rotation[k0 + c]) {
          a0 += s[0] * v, a1 += s[1] * v, a2 += s[2] * v;
        } else {
          a3 += s[3] * v, a4 += s[4] * v, a5 += s[5] * v;
        }
      }
      }
    }
    std::array<S, 6>& C = ws.articulated_bias[J.child];
    C[0] = a0, C[1] = a1, C[2] = a2, C[3] = a3, C[4] = a4, C[5] = a5;
    carried = J.child;
  }
  return true;
}
#define KANESENS_INSTANTIATE(S) template bool articulated_body_accelerations<S>(const Model&, Workspace<S>&);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE

// The same on the planar path (math/planar.hpp): motion and force vectors (ω_z, x, y), an
// articulated inertia a symmetric 3×3 (entries 00, 11, 22, 01, 02, 12), every joint of one speed.
// On every scalar: dual and multi-tangent passes of a planar chain (J v, sensitivities) then cost
// O(n) like the values, where forming and factoring M on the tangent scalar costs O(n³).
// With r = Q_C − Q_P in the plane, X = [1 0 0; −r_y 1 0; r_x 0 1] moves motion to the child and
// Xᵀ force to the parent; Xᵀ I X keeps the translational block and changes the first row.
namespace detail {
template <class S>
bool articulated_body_accelerations_planar(const Model& m, Workspace<S>& ws) {
  for (int b = 0; b < m.nbody(); ++b) {
    const PlanarInertia<S>& I = ws.inertia_planar[b];
    ws.articulated_inertia_planar[b] = {I.I, I.m, I.m, -I.hy, I.hx, S(0)};
    const PVec<S>& w = ws.wrench_planar[b];
    ws.articulated_bias_planar[b] = {-w[0], -w[1], -w[2]};
  }
  S* x = ws.udot.data();  // u/D on the way in, u̇ out
  for (auto it = m.joint_order.rbegin(); it != m.joint_order.rend(); ++it) {
    const Joint& J = m.joints[*it];
    const int k0 = J.u_offset;
    const std::array<S, 6>& I = ws.articulated_inertia_planar[J.child];
    const std::array<S, 3>& p = ws.articulated_bias_planar[J.child];
    const S I00 = I[0], I11 = I[1], I22 = I[2], I01 = I[3], I02 = I[4], I12 = I[5];
    const S rx = ws.joint_offset[*it][0], ry = ws.joint_offset[*it][1];
    S U0 = S(0), U1 = S(0), U2 = S(0), d = S(0), u = S(0);
    if (J.nu == 1) {
      const PVec<S>& s = ws.partial_planar[k0];
      if (double sg; constant_planar_rotation(m, ws, k0, sg)) {
        U0 = times_sign(I00, sg), U1 = times_sign(I01, sg), U2 = times_sign(I02, sg);
        d = times_sign(U0, sg);
        u = ws.forcing[k0] - times_sign(p[0], sg);
      } else {
        U0 = I00 * s[0] + I01 * s[1] + I02 * s[2];
        U1 = I01 * s[0] + I11 * s[1] + I12 * s[2];
        U2 = I02 * s[0] + I12 * s[1] + I22 * s[2];
        d = s[0] * U0 + s[1] * U1 + s[2] * U2;
        u = ws.forcing[k0] - (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]);
      }
      if (!(math::value_of(d) > 0)) return false;
    }
    const S dinv = J.nu == 1 ? S(1.0 / d) : S(0);
    // U' = Xᵀ U, W = U'/D.
    const S V0 = J.parent >= 0 ? S(U0 + rx * U2 - ry * U1) : U0;
    const S W0 = V0 * dinv, W1 = U1 * dinv, W2 = U2 * dinv, ud = u * dinv;
    if (J.nu == 1) {
      x[k0] = ud;
      ws.articulated_columns_planar[k0] = {W0, W1, W2};
    }
    if (J.parent < 0) continue;
    // Xᵀ I X − U' Wᵀ and Xᵀ p + U' u/D, added to the parent.
    const S S01 = I01 - ry * I11 + rx * I12, S02 = I02 - ry * I12 + rx * I22;
    const S S00 = I00 - ry * I01 + rx * I02 - ry * S01 + rx * S02;
    std::array<S, 6>& P = ws.articulated_inertia_planar[J.parent];
    P[0] += S00 - V0 * W0;
    P[1] += I11 - U1 * W1;
    P[2] += I22 - U2 * W2;
    P[3] += S01 - V0 * W1;
    P[4] += S02 - V0 * W2;
    P[5] += I12 - U1 * W2;
    std::array<S, 3>& pP = ws.articulated_bias_planar[J.parent];
    pP[0] += p[0] + rx * p[2] - ry * p[1] + V0 * ud;
    pP[1] += p[1] + U1 * ud;
    pP[2] += p[2] + U2 * ud;
  }
  // Roots to leaves: u̇ = u/D − Wᵀ δa_P, δa_C = X δa_P + s u̇, δa carried along a chain.
  S a0 = S(0), a1 = S(0), a2 = S(0);
  int carried = -1;
  for (int ji : m.joint_order) {
    const Joint& J = m.joints[ji];
    const int k0 = J.u_offset;
    if (J.parent < 0) {
      a0 = a1 = a2 = S(0);
    } else if (J.parent != carried) {
      const std::array<S, 3>& A = ws.articulated_bias_planar[J.parent];
      a0 = A[0], a1 = A[1], a2 = A[2];
    }
    S ud = S(0);
    if (J.nu == 1) {
      const std::array<S, 3>& W = ws.articulated_columns_planar[k0];
      ud = x[k0] - (W[0] * a0 + W[1] * a1 + W[2] * a2);
      x[k0] = ud;
    }
    const S rx = ws.joint_offset[ji][0], ry = ws.joint_offset[ji][1];
    a1 -= a0 * ry;
    a2 += a0 * rx;
    if (J.nu == 1) {
      const PVec<S>& s = ws.partial_planar[k0];
      if (double sg; constant_planar_rotation(m, ws, k0, sg))
        a0 += times_sign(ud, sg);
      else
        a0 += s[0] * ud, a1 += s[1] * ud, a2 += s[2] * ud;
    }
    ws.articulated_bias_planar[J.child] = {a0, a1, a2};
    carried = J.child;
  }
  return true;
}
#define KANESENS_INSTANTIATE(S) template bool articulated_body_accelerations_planar<S>(const Model&, Workspace<S>&);
KANESENS_FOR_EACH_DYNAMICS_SCALAR(KANESENS_INSTANTIATE)
#undef KANESENS_INSTANTIATE
}  // namespace detail

}  // namespace kanesens::dynamics
