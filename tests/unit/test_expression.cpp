#include <gtest/gtest.h>

#include <cmath>

#include "math/dual.hpp"
#include "model/expr/expression.hpp"
#include "../support/layers.hpp"

using namespace kanesens::testing;
using namespace kanesens::model::expr;

namespace {
NameTable table() {
  NameTable t;
  t.add("a", {VarKind::parameter, 0});
  t.add("b", {VarKind::parameter, 1});
  t.add("t", {VarKind::time, 0});
  t.add("elbow.q", {VarKind::coordinate, 0});
  t.add("elbow.u", {VarKind::speed, 0});
  return t;
}
double eval(const std::string& s, double a = 2, double b = 3, double t = 0.5, double q = 0.25, double u = -1) {
  const NameTable names = table();
  const Expression e = compile(s, names, {"f.yaml", 3, 4}, "k");
  const double p[] = {a, b};
  Inputs<double> in;
  in.parameters = p;
  in.coordinates = &q;
  in.speeds = &u;
  in.time = t;
  return e.evaluate(in);
}
std::string error_of(const std::string& s) {
  try {
    eval(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Expression, PrecedenceAndAssociativity) {
  EXPECT_DOUBLE_EQ(eval("1+2*3"), 7);
  EXPECT_DOUBLE_EQ(eval("(1+2)*3"), 9);
  EXPECT_DOUBLE_EQ(eval("2^3^2"), 512);  // right-associative
  EXPECT_DOUBLE_EQ(eval("-2^2"), -4);    // -(2^2)
  EXPECT_DOUBLE_EQ(eval("2**-1"), 0.5);
  EXPECT_DOUBLE_EQ(eval("8/2/2"), 2);
  EXPECT_DOUBLE_EQ(eval("1.5e-3*2"), 3e-3);
  EXPECT_DOUBLE_EQ(eval("a*b^2/12"), 2 * 9 / 12.0);
}

TEST(Expression, FunctionsAndVariables) {
  EXPECT_NEAR(eval("sin(pi/2) + cos(0) + sqrt(16) + abs(-2) + exp(0) + log(1)"), 1 + 1 + 4 + 2 + 1, 1e-15);
  EXPECT_NEAR(eval("atan2(1, 1)"), M_PI / 4, 1e-15);
  EXPECT_DOUBLE_EQ(eval("min(a, b) + max(a, b)"), 5);
  EXPECT_DOUBLE_EQ(eval("-0.1*elbow.u + t + elbow.q"), 0.1 + 0.5 + 0.25);
}

TEST(Expression, NegativeBaseIntegerPower) { EXPECT_DOUBLE_EQ(eval("(-2)^3"), -8); }

TEST(Expression, ConstantFoldingMarksConstants) {
  const NameTable names = table();
  EXPECT_TRUE(compile("2*pi/4", names, {}, "k").is_constant());
  EXPECT_FALSE(compile("2*a", names, {}, "k").is_constant());
  EXPECT_TRUE(compile("2*a", names, {}, "k").uses_parameters());
  EXPECT_FALSE(compile("2*a", names, {}, "k").uses_state());
  EXPECT_TRUE(compile("sin(t)", names, {}, "k").uses_state());
}

TEST(Expression, DualGivesExactDerivative) {
  const NameTable names = table();
  const Expression e = compile("a^2*sin(b) + exp(a/b)", names, {}, "k");
  const Dual p[] = {Dual(2, 1), Dual(3, 0)};  // d/da
  Inputs<Dual> in;
  in.parameters = p;
  const Dual r = e.evaluate(in);
  EXPECT_NEAR(r.d, 2 * 2 * std::sin(3.0) + std::exp(2.0 / 3) / 3, 1e-14);
}

TEST(Expression, ErrorsNameFileKeyAndPosition) {
  std::string e = error_of("a*(b");
  EXPECT_NE(e.find("f.yaml:3:4: k:"), std::string::npos) << e;
  EXPECT_NE(e.find("missing ')'"), std::string::npos) << e;
  e = error_of("aa + 1");
  EXPECT_NE(e.find("unknown name 'aa'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'a'"), std::string::npos) << e;
  e = error_of("sinn(a)");
  EXPECT_NE(e.find("unknown function 'sinn'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'sin'"), std::string::npos) << e;
  EXPECT_NE(error_of("1 +").find("ends early"), std::string::npos);
  EXPECT_NE(error_of("2 3").find("unexpected '3'"), std::string::npos);
  EXPECT_NE(error_of("").find("empty"), std::string::npos);
  EXPECT_NE(error_of("atan2(1)").find("takes 2 arguments"), std::string::npos);
}
