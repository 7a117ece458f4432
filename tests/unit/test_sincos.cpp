// math::sincos2, the position stage's two-angle sin and cos: within one unit in the last place of
// the long-double sinl and cosl (which we did not write) over joint-angle ranges, many turns, the
// hardest arguments (doubles next to multiples of π/2) and tiny angles; lanes out of its range
// (huge, infinite, NaN) as the C library gives them; and each angle's result independent of the
// angle it is paired with. math::sincos4, its four-lane form, gives every lane sincos2's bits.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "math/sincos.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

namespace {

using kanesens::math::sincos2;
using kanesens::math::sincos4;

// |got − ref| in units of the last place of the double nearest ref.
double ulps(double got, long double ref) {
  const double r = std::fabs(static_cast<double>(ref));
  const double ulp = r == 0 ? std::numeric_limits<double>::denorm_min() : std::nextafter(r, INFINITY) - r;
  return static_cast<double>(std::fabs(static_cast<long double>(got) - ref) / ulp);
}

// The largest error over n pairs drawn by gen.
template <class Gen>
double max_error(Gen gen, int n) {
  double worst = 0;
  for (int k = 0; k < n; ++k) {
    const double x[2] = {gen(), gen()};
    double s[2], c[2];
    sincos2(x, s, c);
    for (int i = 0; i < 2; ++i) {
      worst = std::max(worst, ulps(s[i], std::sin(static_cast<long double>(x[i]))));
      worst = std::max(worst, ulps(c[i], std::cos(static_cast<long double>(x[i]))));
    }
  }
  return worst;
}

TEST(SinCos2, WithinOneUlpOfLongDouble) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> turn(-7.0, 7.0), turns(-2e4, 2e4), far(-8.2e5, 8.2e5), tiny(-1e-5, 1e-5);
  EXPECT_LT(max_error([&] { return turn(rng); }, 200000), 1.0);
  EXPECT_LT(max_error([&] { return turns(rng); }, 100000), 1.0);
  EXPECT_LT(max_error([&] { return far(rng); }, 100000), 1.0);
  EXPECT_LT(max_error([&] { return tiny(rng); }, 20000), 1.0);
}

// Doubles within a few units of k π/2: the reduced angle is tiny, so any loss in the reduction shows.
TEST(SinCos2, WithinOneUlpNextToMultiplesOfHalfPi) {
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<long> k(-520000, 520000);
  std::uniform_int_distribution<int> step(-4, 4);
  const long double half_pi = 1.570796326794896619231321691639751442L;
  const double worst = max_error(
      [&] {
        double x = static_cast<double>(static_cast<long double>(k(rng)) * half_pi);
        for (int s = step(rng); s != 0; s += s > 0 ? -1 : 1) x = std::nextafter(x, s > 0 ? INFINITY : -INFINITY);
        return x;
      },
      100000);
  EXPECT_LT(worst, 1.0);
}

TEST(SinCos2, ExactAtZeroAndOutOfRangeLanesAsTheCLibrary) {
  double s[2], c[2];
  const double zeros[2] = {0.0, -0.0};
  sincos2(zeros, s, c);
  EXPECT_EQ(s[0], 0.0);
  EXPECT_EQ(c[0], 1.0);
  EXPECT_EQ(s[1], 0.0);
  EXPECT_EQ(c[1], 1.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (double odd : {1e7, -3.3e12, 1e300, inf, -inf, std::numeric_limits<double>::quiet_NaN()}) {
    const double x[2] = {0.7, odd};
    sincos2(x, s, c);
    if (std::isnan(std::sin(odd))) {
      EXPECT_TRUE(std::isnan(s[1]) && std::isnan(c[1])) << odd;
    } else {
      EXPECT_EQ(s[1], std::sin(odd)) << odd;
      EXPECT_EQ(c[1], std::cos(odd)) << odd;
    }
    // The in-range partner is unaffected.
    double s0[2], c0[2];
    const double y[2] = {0.7, 0.1};
    sincos2(y, s0, c0);
    EXPECT_EQ(s[0], s0[0]) << odd;
    EXPECT_EQ(c[0], c0[0]) << odd;
  }
}

// Either lane gives an angle the same bits whatever the other holds.
TEST(SinCos2, ResultDoesNotDependOnThePartner) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> angle(-50.0, 50.0);
  for (int k = 0; k < 10000; ++k) {
    const double a = angle(rng), b = angle(rng), c = angle(rng);
    double s1[2], c1[2], s2[2], c2[2];
    const double x1[2] = {a, b}, x2[2] = {c, a};
    sincos2(x1, s1, c1);
    sincos2(x2, s2, c2);
    ASSERT_EQ(s1[0], s2[1]);
    ASSERT_EQ(c1[0], c2[1]);
  }
}

// Each lane of sincos4 has sincos2's bits (a position stage's values do not depend on how its
// angles are grouped): angles in range, far ones, and lanes out of range or not finite.
TEST(SinCos4, EachLaneAsSinCos2) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> angle(-50.0, 50.0), far(-8.2e5, 8.2e5);
  std::uniform_int_distribution<int> pick(0, 9);
  const double inf = std::numeric_limits<double>::infinity();
  const double odd[] = {1e7, -3.3e12, inf, -0.0, std::numeric_limits<double>::quiet_NaN(), 1.5707963267948966};
  for (int k = 0; k < 20000; ++k) {
    double x[4];
    for (double& v : x) {
      const int p = pick(rng);
      v = p < 6 ? angle(rng) : p < 8 ? far(rng) : odd[static_cast<std::size_t>(k + p) % 6];
    }
    double s4[4], c4[4], s2[4], c2[4];
    sincos4(x, s4, c4);
    sincos2(x, s2, c2);
    sincos2(x + 2, s2 + 2, c2 + 2);
    for (int i = 0; i < 4; ++i) {
      if (std::isnan(x[i])) {
        ASSERT_TRUE(std::isnan(s4[i]) && std::isnan(c4[i]));
        continue;
      }
      ASSERT_EQ(std::bit_cast<std::uint64_t>(s4[i]), std::bit_cast<std::uint64_t>(s2[i])) << x[i];
      ASSERT_EQ(std::bit_cast<std::uint64_t>(c4[i]), std::bit_cast<std::uint64_t>(c2[i])) << x[i];
    }
  }
}

}  // namespace

}  // namespace KANESENS_UNITY_ID
