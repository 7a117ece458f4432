#include <gtest/gtest.h>

#include <cmath>

#include "math/dual.hpp"
#include "model/expr/expression.hpp"
#include "../support/layers.hpp"

namespace KANESENS_UNITY_ID {  // this file's own names in a unity batch (tests/CMakeLists.txt)

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

namespace {
// Three coordinates x, y, z, time t and a parameter a; points where every function is defined.
NameTable gradient_table() {
  NameTable t;
  t.add("a", {VarKind::parameter, 0});
  t.add("t", {VarKind::time, 0});
  t.add("x", {VarKind::coordinate, 0});
  t.add("y", {VarKind::coordinate, 1});
  t.add("z", {VarKind::coordinate, 2});
  return t;
}
template <class S>
S value_at(const Expression& e, const S* q, S t, const S* p) {
  Inputs<S> in;
  in.parameters = p;
  in.coordinates = q;
  in.time = t;
  return e.evaluate(in);
}
}  // namespace

// The reverse sweep against central differences of the value (a check that does not use dual
// numbers), and its value against evaluate bit for bit, for every operation of the language.
TEST(Expression, GradientMatchesDifferencesForEveryOperation) {
  const NameTable names = gradient_table();
  const char* cases[] = {
      "x + y - z", "x*y*z - t*x", "x/y + a/(z*t)", "-x + -(y*z)", "x^y + y^2.5", "x^3 - y^-2 + z^0",
      "sin(x*y) + cos(z - t)", "tan(x) * asin(y) - acos(z)", "atan(x*t) + exp(y - z) - log(x + z)",
      "sqrt(x*y + z) + abs(y - x) + abs(z - 1)", "atan2(y, x) - atan2(z*t, -y)", "min(x, y*z) + max(y, t*z)",
      "a*cos(x + y) - a*sin(x + y + z) - x*x*x", "x"};
  const double q0[] = {0.7, 0.4, 0.3}, t0 = 1.3, p[] = {1.7};
  Tape<double> tape;
  for (const char* text : cases) {
    SCOPED_TRACE(text);
    const Expression e = compile(text, names, {}, "k");
    tape.resize(e.size());
    double grad[3] = {0, 0, 0}, d_time = -1;
    Inputs<double> in;
    in.parameters = p;
    in.coordinates = q0;
    in.time = t0;
    const double g = e.gradient(in, tape, grad, d_time);
    EXPECT_EQ(g, e.evaluate(in));
    const double h = 1e-6;
    for (int i = 0; i < 3; ++i) {
      double qp[3] = {q0[0], q0[1], q0[2]}, qm[3] = {q0[0], q0[1], q0[2]};
      qp[i] += h, qm[i] -= h;
      const double fd = (value_at(e, qp, t0, p) - value_at(e, qm, t0, p)) / (2 * h);
      EXPECT_NEAR(grad[i], fd, 1e-7 * (1 + std::abs(fd))) << "coordinate " << i;
    }
    const double fd_t = (value_at(e, q0, t0 + h, p) - value_at(e, q0, t0 - h, p)) / (2 * h);
    EXPECT_NEAR(d_time, fd_t, 1e-7 * (1 + std::abs(fd_t)));
  }
}

// On duals along a direction v: the ε parts of the gradient are the Hessian times v, checked
// against central differences of the gradient's values; coordinates it does not read are left
// as the caller set them.
TEST(Expression, GradientOnDualsGivesHessianTimesDirection) {
  const NameTable names = gradient_table();
  const Expression e = compile("a*sin(x*y) - y^3/z + t*x*x + atan2(z, x)", names, {}, "k");
  Tape<Dual> tape;
  tape.resize(e.size());
  const double q0[] = {0.7, 0.4, 0.3}, v[] = {0.3, -1.1, 0.6}, vt = 0.8, t0 = 1.3;
  const Dual p[] = {Dual(1.7)};
  auto gradient_values = [&](double s, double* out) {
    Tape<double> tp;
    tp.resize(e.size());
    const double q[] = {q0[0] + s * v[0], q0[1] + s * v[1], q0[2] + s * v[2]}, pd[] = {1.7};
    Inputs<double> in;
    in.parameters = pd;
    in.coordinates = q;
    in.time = t0 + s * vt;
    out[0] = out[1] = out[2] = 0;
    e.gradient(in, tp, out, out[3]);
  };
  Dual q[3], grad[4];
  for (int i = 0; i < 3; ++i) q[i] = Dual(q0[i], v[i]);
  Inputs<Dual> in;
  in.parameters = p;
  in.coordinates = q;
  in.time = Dual(t0, vt);
  const Dual g = e.gradient(in, tape, grad, grad[3]);
  // ε part of the value: the directional derivative ∇g·(v, vt).
  double plain[4], ahead[4], behind[4];
  gradient_values(0, plain);
  EXPECT_NEAR(g.d, plain[0] * v[0] + plain[1] * v[1] + plain[2] * v[2] + plain[3] * vt, 1e-14);
  const double h = 1e-6;
  gradient_values(h, ahead);
  gradient_values(-h, behind);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(grad[i].v, plain[i]) << i;
    const double fd = (ahead[i] - behind[i]) / (2 * h);
    EXPECT_NEAR(grad[i].d, fd, 1e-7 * (1 + std::abs(fd))) << i;
  }
  // Only the coordinates read are touched.
  const Expression only_y = compile("y*y", names, {}, "k");
  double g2[3] = {5, 0, 7}, dt = 1;
  Tape<double> t2;
  t2.resize(only_y.size());
  Inputs<double> in2;
  in2.coordinates = q0;
  only_y.gradient(in2, t2, g2, dt);
  EXPECT_EQ(g2[0], 5);
  EXPECT_EQ(g2[1], 2 * q0[1]);
  EXPECT_EQ(g2[2], 7);
  EXPECT_EQ(dt, 0);
}

}  // namespace KANESENS_UNITY_ID
