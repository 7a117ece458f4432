// MultiDual<N>: every tangent equals what the single-tangent Dual gives with the same seed
// (Dual is itself checked against finite differences and closed forms elsewhere), through
// arithmetic, the elementary functions (sin_cos bit for bit as sin and cos), Eigen products and a
// nested DualT for second derivatives;
// has_tangent tells constants from the rest; and rotate_constant_inertia, the position stage's
// shortcut for an inertia without tangents, equals rotate_inertia's products.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <random>

#include "math/dual.hpp"
#include "math/multi_dual.hpp"
#include "math/spatial.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using kanesens::math::Dual;
using kanesens::math::DualT;
using kanesens::math::MultiDual;

// A function of three inputs that exercises every operation and function of the type.
template <class S>
S kitchen_sink(const S& x, const S& y, const S& z) {
  using std::abs, std::acos, std::asin, std::atan, std::atan2, std::cos, std::exp, std::log, std::pow, std::sin,
      std::sqrt, std::tan;
  S r = x * y - z / x + 2.0 * x - y / 3.0 + 1.5 - x;
  r += sin(x) * cos(y) + tan(z) + asin(z / 4.0) + acos(y / 5.0) + atan(x);
  r -= atan2(y, x) * exp(z) + log(x * x + 1.0) + sqrt(y * y + 2.0) + abs(z - x);
  r *= pow(x * x + 0.5, y) + 1.0 / (x + 4.0);
  r /= (3.0 - z) * 0.5;
  r += (x < y ? x : y) + (-z) + (x - 0.25);
  r -= 0.125;
  return r;
}

template <int N>
void expect_matches_dual() {
  std::mt19937 rng(N);
  std::uniform_real_distribution<double> u(-1, 1);
  const double xv = 0.7, yv = -0.4, zv = 0.3;
  double seeds[3][N];
  for (auto& row : seeds)
    for (double& s : row) s = u(rng);
  MultiDual<N> x(xv), y(yv), z(zv);
  x.set_tangents([&](int i) { return seeds[0][i]; }, N);
  y.set_tangents([&](int i) { return seeds[1][i]; }, N);
  z.set_tangents([&](int i) { return seeds[2][i]; }, N);
  const MultiDual<N> r = kitchen_sink(x, y, z);
  for (int i = 0; i < N; ++i) {
    const Dual d = kitchen_sink(Dual(xv, seeds[0][i]), Dual(yv, seeds[1][i]), Dual(zv, seeds[2][i]));
    EXPECT_DOUBLE_EQ(r.v, d.v);
    EXPECT_NEAR(r.d(i), d.d, 1e-13 * (1 + std::abs(d.d))) << "tangent " << i;
  }
}

TEST(MultiDual, EveryTangentMatchesDual) {
  expect_matches_dual<1>();
  expect_matches_dual<3>();
  expect_matches_dual<4>();
  expect_matches_dual<6>();
  expect_matches_dual<7>();
  expect_matches_dual<8>();
  expect_matches_dual<13>();
}

// Tangent i of kitchen_sink on MultiDual<N>, seeded as for N = 2 in directions 0 and 1.
template <int N>
std::array<double, 3> first_two_tangents() {
  const double seeds[3][2] = {{0.3, -1.1}, {0.8, 0.25}, {-0.6, 0.9}};
  MultiDual<N> x(0.7), y(-0.4), z(0.3);
  x.set_tangents([&](int i) { return i < 2 ? seeds[0][i] : 0.5; }, N);
  y.set_tangents([&](int i) { return i < 2 ? seeds[1][i] : -0.5; }, N);
  z.set_tangents([&](int i) { return i < 2 ? seeds[2][i] : 0.25; }, N);
  MultiDual<N> r = kitchen_sink(x, y, z);
  r.subtract_tangents(y, 0.75);
  return {r.v, r.d(0), r.d(1)};
}

TEST(MultiDual, TangentsDoNotDependOnTheWidth) {
  // Narrow widths take narrower packs (MultiDual::lanes), and the value shares the first pack
  // with the tangents where that takes no pack more (up to 7 tangents with 8-lane registers; 3,
  // 5–7, 9–11, 13–15 with 4-lane ones); the arithmetic is lane by lane, so a direction's tangent is
  // the same bits at every width and in either layout.
  const std::array<double, 3> two = first_two_tangents<2>();
  EXPECT_EQ(first_two_tangents<4>(), two);
  EXPECT_EQ(first_two_tangents<6>(), two);
  EXPECT_EQ(first_two_tangents<7>(), two);
  EXPECT_EQ(first_two_tangents<13>(), two);
  EXPECT_EQ(MultiDual<2>::packs, 1);
  EXPECT_EQ(MultiDual<4>::packs, MultiDual<4>::register_lanes >= 4 ? 1 : 2);  // 2 with SSE2 only
  EXPECT_EQ(MultiDual<6>::value_in_pack, MultiDual<6>::register_lanes >= 4);
  EXPECT_EQ(MultiDual<13>::value_in_pack, MultiDual<13>::register_lanes == 4);  // 8 lanes: 13 + 1 take a pack more
  EXPECT_FALSE(MultiDual<4>::value_in_pack);
  if (MultiDual<6>::value_in_pack) {
    EXPECT_EQ(sizeof(MultiDual<6>), 8 * sizeof(double));
    EXPECT_EQ(sizeof(MultiDual<7>), 8 * sizeof(double));
  }
}

TEST(MultiDual, SeedingAndUnusedLanes) {
  const auto x = MultiDual<5>::seeded(2.0, 3);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(x.d(i), i == 3 ? 1.0 : 0.0);
  MultiDual<5> y(1.0);
  y.set_tangents([](int i) { return 10.0 + i; }, 2);  // fewer than N: the rest are 0
  EXPECT_EQ(y.d(0), 10.0);
  EXPECT_EQ(y.d(1), 11.0);
  for (int i = 2; i < 5; ++i) EXPECT_EQ(y.d(i), 0.0);
  // Padding lanes of the last pack stay 0 through arithmetic (a division would turn garbage
  // into NaN and isfinite would see it).
  const MultiDual<5> z = (x * y + 1.0) / (y + 3.0);
  EXPECT_TRUE(isfinite(z));
  EXPECT_TRUE(kanesens::math::is_multi_dual_v<MultiDual<5>>);
  EXPECT_FALSE(kanesens::math::is_multi_dual_v<Dual>);
  EXPECT_FALSE(isfinite(MultiDual<5>(1.0) / MultiDual<5>(0.0)));
}

TEST(MultiDual, EigenProductsMatchDual) {
  constexpr int N = 6;
  using M3 = Eigen::Matrix<MultiDual<N>, 3, 3>;
  using D3 = Eigen::Matrix<Dual, 3, 3>;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3d A0, B0, At[N], Bt[N];
  A0.setRandom();
  B0.setRandom();
  for (int i = 0; i < N; ++i) {
    At[i].setRandom();
    Bt[i].setRandom();
  }
  M3 A, B;
  for (int k = 0; k < 9; ++k) {
    A(k) = MultiDual<N>(A0(k));
    A(k).set_tangents([&](int i) { return At[i](k); }, N);
    B(k) = MultiDual<N>(B0(k));
    B(k).set_tangents([&](int i) { return Bt[i](k); }, N);
  }
  const M3 C = A * B * A.transpose() + 2.0 * B;
  const Eigen::Matrix<MultiDual<N>, 3, 1> v = A.col(0).cross(B.col(1));
  for (int i = 0; i < N; ++i) {
    D3 Ad, Bd;
    for (int k = 0; k < 9; ++k) {
      Ad(k) = Dual(A0(k), At[i](k));
      Bd(k) = Dual(B0(k), Bt[i](k));
    }
    const D3 Cd = Ad * Bd * Ad.transpose() + 2.0 * Bd;
    const Eigen::Matrix<Dual, 3, 1> vd = Ad.col(0).cross(Bd.col(1));
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(C(k).d(i), Cd(k).d, 1e-13);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(v[k].d(i), vd[k].d, 1e-13);
  }
}

TEST(MultiDual, NestsForSecondDerivatives) {
  // f = sin(x) y², with x, y carrying two tangents each and an outer ε for d/dx:
  // the outer tangent's inner tangents are the mixed second derivatives.
  using MD = MultiDual<2>;
  MD x(0.4), y(1.3);
  x.set_d(0, 1.0);  // inner direction 0: x
  y.set_d(1, 1.0);  // inner direction 1: y
  const DualT<MD> X(x, MD(1.0)), Y(y, MD(0.0));  // outer direction: x
  const DualT<MD> f = sin(X) * Y * Y;
  EXPECT_NEAR(f.v.v, std::sin(0.4) * 1.69, 1e-15);
  EXPECT_NEAR(f.d.v, std::cos(0.4) * 1.69, 1e-15);             // ∂f/∂x
  EXPECT_NEAR(f.d.d(0), -std::sin(0.4) * 1.69, 1e-15);         // ∂²f/∂x²
  EXPECT_NEAR(f.d.d(1), std::cos(0.4) * 2 * 1.3, 1e-15);       // ∂²f/∂x∂y
  EXPECT_EQ(kanesens::math::value_of(f), f.v.v);
}

TEST(MultiDual, SinCosIsSinAndCosBitForBit) {
  // sin_cos shares the value's sine and cosine; every part equals what sin and cos give, at each
  // level of DualT<MultiDual> (the nesting of a general constraint's gradient in a Jacobian pass).
  using MD = MultiDual<4>;
  MD x(0.7), dx(-1.3);
  for (int k = 0; k < 4; ++k) x.set_d(k, 0.25 * k - 0.6), dx.set_d(k, 0.5 - 0.3 * k);
  const DualT<MD> a(x, dx);
  DualT<MD> s, c;
  sin_cos(a, s, c);
  const DualT<MD> s_ref = sin(a), c_ref = cos(a);
  for (const auto& [got, want] : {std::pair{s, s_ref}, std::pair{c, c_ref}}) {
    EXPECT_EQ(got.v.v, want.v.v);
    EXPECT_EQ(got.d.v, want.d.v);
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(got.v.d(k), want.v.d(k)) << k;
      EXPECT_EQ(got.d.d(k), want.d.d(k)) << k;
    }
  }
  double sd, cd;
  kanesens::math::sin_cos(0.7, sd, cd);
  EXPECT_EQ(sd, std::sin(0.7));
  EXPECT_EQ(cd, std::cos(0.7));
}

TEST(MultiDual, HasTangentAtAnyDepth) {
  using kanesens::math::has_tangent;
  EXPECT_FALSE(has_tangent(1.5));
  EXPECT_FALSE(has_tangent(MultiDual<10>(2.0)));
  EXPECT_TRUE(has_tangent(MultiDual<10>::seeded(2.0, 9)));
  EXPECT_FALSE(has_tangent(Dual(1.0, 0.0)));
  EXPECT_TRUE(has_tangent(Dual(1.0, -1e-300)));
  EXPECT_FALSE(has_tangent(DualT<Dual>(Dual(1.0, 0.0), Dual(0.0, 0.0))));
  EXPECT_TRUE(has_tangent(DualT<Dual>(Dual(1.0, 0.0), Dual(0.0, 3.0))));  // inner tangent of the outer
  EXPECT_TRUE(has_tangent(DualT<Dual>(Dual(1.0, 2.0), Dual(0.0, 0.0))));
}

// R I Rᵀ for a constant I and an R with tangents: rotate_constant_inertia against the general
// products of rotate_inertia (values bit for bit, tangents to round-off) and against a
// single-tangent Dual per direction.
TEST(MultiDual, ConstantInertiaRotatesAsTheGeneralProduct) {
  constexpr int N = 10;
  using MD = MultiDual<N>;
  using kanesens::math::SpatialInertia;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  // A rotation with tangents: R(θ) for three angles, each angle seeded in random directions.
  double theta[3], seeds[3][N];
  for (int k = 0; k < 3; ++k) {
    theta[k] = 2 * u(rng);
    for (double& s : seeds[k]) s = u(rng);
  }
  auto rotation = [&](auto a, auto b, auto c) {
    using S = decltype(a);
    const Eigen::Matrix<S, 3, 3> Rx = kanesens::math::axis_angle<S>(Eigen::Matrix<S, 3, 1>(S(1), S(0), S(0)), a);
    const Eigen::Matrix<S, 3, 3> Ry = kanesens::math::axis_angle<S>(Eigen::Matrix<S, 3, 1>(S(0), S(1), S(0)), b);
    const Eigen::Matrix<S, 3, 3> Rz = kanesens::math::axis_angle<S>(Eigen::Matrix<S, 3, 1>(S(0), S(0), S(1)), c);
    return Eigen::Matrix<S, 3, 3>(Rz * Ry * Rx);
  };
  MD a[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = MD(theta[k]);
    a[k].set_tangents([&](int i) { return seeds[k][i]; }, N);
  }
  const Eigen::Matrix<MD, 3, 3> R = rotation(a[0], a[1], a[2]);
  auto inertia = [](auto zero) {
    using S = decltype(zero);
    SpatialInertia<S> X;
    X.m = S(2.5);
    X.h = Eigen::Matrix<S, 3, 1>(S(0.3), S(-0.7), S(0.2));
    X.I << S(0.9), S(0.11), S(-0.05), S(0.11), S(0.6), S(0.08), S(-0.05), S(0.08), S(0.4);
    return X;
  };
  SpatialInertia<MD> fast, general;
  kanesens::math::rotate_constant_inertia<MD>(inertia(MD(0.0)), R, fast);
  kanesens::math::rotate_inertia<MD>(inertia(MD(0.0)), R, general);
  Eigen::Matrix3d R0;
  for (int k = 0; k < 9; ++k) R0(k) = R(k).v;
  SpatialInertia<double> values;
  kanesens::math::rotate_inertia<double>(inertia(0.0), R0, values);
  for (int k = 0; k < 9; ++k) {
    EXPECT_EQ(fast.I(k).v, values.I(k)) << k;  // the double path's values, bit for bit
    EXPECT_EQ(fast.I(k).v, fast.I(k % 3 * 3 + k / 3).v) << k;  // symmetric
  }
  for (int i = 0; i < N; ++i) {
    const auto Rd = rotation(Dual(theta[0], seeds[0][i]), Dual(theta[1], seeds[1][i]), Dual(theta[2], seeds[2][i]));
    SpatialInertia<Dual> d;
    kanesens::math::rotate_inertia<Dual>(inertia(Dual(0.0)), Rd, d);
    for (int k = 0; k < 9; ++k) {
      EXPECT_NEAR(fast.I(k).d(i), general.I(k).d(i), 1e-14) << "direction " << i << ", entry " << k;
      EXPECT_NEAR(fast.I(k).d(i), d.I(k).d, 1e-14) << "direction " << i << ", entry " << k;
    }
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(fast.h[k].d(i), d.h[k].d, 1e-14);
    EXPECT_EQ(fast.m.d(i), 0.0);
  }
}

// R I Rᵀ for a diagonal I: rotate_diagonal_inertia against rotate_inertia, values bit for bit on
// double (the general products by the zero entries add exact zeros) and tangents to round-off on
// a multi-tangent scalar with tangents in R and in I's diagonal.
TEST(MultiDual, DiagonalInertiaRotatesAsTheGeneralProduct) {
  constexpr int N = 4;
  using MD = MultiDual<N>;
  using kanesens::math::SpatialInertia;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d R0 = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    SpatialInertia<double> X;
    X.m = 1 + u(rng) * u(rng);
    X.h = Eigen::Vector3d(u(rng), u(rng), u(rng));
    X.I.setZero();
    for (int k = 0; k < 3; ++k) X.I(k, k) = 1 + u(rng);
    SpatialInertia<double> fast, general;
    kanesens::math::rotate_diagonal_inertia<double>(X, R0, fast);
    kanesens::math::rotate_inertia<double>(X, R0, general);
    for (int k = 0; k < 9; ++k) EXPECT_EQ(fast.I(k), general.I(k)) << "trial " << trial << ", entry " << k;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(fast.h[k], general.h[k]);
    EXPECT_EQ(fast.m, general.m);

    Eigen::Matrix<MD, 3, 3> R;
    SpatialInertia<MD> Xd;
    for (int k = 0; k < 9; ++k) {
      R(k) = MD(R0(k));
      R(k).set_tangents([&](int) { return u(rng); }, N);
    }
    Xd.m = MD(X.m);
    for (int k = 0; k < 3; ++k) Xd.h[k] = MD(X.h[k]);
    Xd.I.setConstant(MD(0.0));
    for (int k = 0; k < 3; ++k) {
      Xd.I(k, k) = MD(X.I(k, k));
      Xd.I(k, k).set_tangents([&](int) { return u(rng); }, N);
    }
    SpatialInertia<MD> fd, gd;
    kanesens::math::rotate_diagonal_inertia<MD>(Xd, R, fd);
    kanesens::math::rotate_inertia<MD>(Xd, R, gd);
    for (int k = 0; k < 9; ++k) {
      EXPECT_EQ(fd.I(k).v, gd.I(k).v) << k;
      for (int i = 0; i < N; ++i) EXPECT_NEAR(fd.I(k).d(i), gd.I(k).d(i), 1e-14) << "entry " << k << ", direction " << i;
    }
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
