// libFuzzer: expression text -> expr::compile + evaluate and gradient (double). Syntax errors must
// be InputErrors; evaluation must not crash (NaN/inf values are fine here: the model build and
// check_parameters report them with the expression's location), and the gradient's value must
// be evaluate's, bit for bit.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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
    const double v = e.evaluate(in);
    Tape<double> tape;
    tape.resize(e.size());
    double d_q[1] = {0}, d_t = 0;
    const double g = e.gradient(in, tape, d_q, d_t);
    if (std::memcmp(&v, &g, sizeof v) != 0 && !(v != v && g != g)) {
      std::fprintf(stderr, "fuzz_expr: gradient's value %.17g differs from evaluate's %.17g\n", g, v);
      std::abort();
    }
  } catch (const kanesens::InputError&) {
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "fuzz_expr: not an InputError: %s\n", ex.what());
    std::abort();
  }
  return 0;
}
