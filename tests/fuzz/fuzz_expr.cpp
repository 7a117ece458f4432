// libFuzzer: expression text -> expr::compile + evaluate (double). Syntax errors must be
// InputErrors; evaluation must not crash (NaN/inf values are fine here: the model build and
// check_parameters report them with the expression's location).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "model/expr/expression.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace kanesens::model::expr;
  static const NameTable names = [] {
    NameTable n;
    n.add("m", {VarKind::parameter, 0});
    n.add("L", {VarKind::parameter, 1});
    n.add("t", {VarKind::time, 0});
    n.add("elbow.q", {VarKind::coordinate, 0});
    n.add("elbow.u", {VarKind::speed, 0});
    return n;
  }();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const Expression e = compile(text, names, {"fuzz.yaml", 1, 1}, "fuzz");
    const double p[2] = {1.5, -0.25}, q[1] = {0.3}, u[1] = {-2.0};
    Inputs<double> in;
    in.parameters = p;
    in.coordinates = q;
    in.speeds = u;
    in.time = 0.7;
    volatile double v = e.evaluate(in);
    (void)v;
  } catch (const kanesens::InputError&) {
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "fuzz_expr: not an InputError: %s\n", ex.what());
    std::abort();
  }
  return 0;
}
