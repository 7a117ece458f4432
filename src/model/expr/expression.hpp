// Expressions in scene files ("m2*L2^2/12", "F0*sin(w*t)", "-0.1*elbow.u"), parsed once at
// model build into a small stack program and evaluated through any Scalar (double or Dual),
// so derivatives with respect to parameters and states are exact.
#pragma once
#include <array>
#include <cassert>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "util/error.hpp"

namespace kanesens::model::expr {

// What a name in an expression refers to. Indices are into the arrays passed to evaluate().
// `quantity`: a value the caller computes and names (a study's outputs, sim/output_plan.hpp).
enum class VarKind : unsigned char { parameter, time, coordinate, speed, quantity };
struct VarRef {
  VarKind kind;
  int index;
};
// The names an expression may use, and what each refers to.
class NameTable {
 public:
  void add(const std::string& name, VarRef ref);
  std::optional<VarRef> find(const std::string& name) const;  // hashed: scenes of 100 000 names
  const std::vector<std::string>& names() const { return names_; }
  // A name that is known but cannot be used as written; compiling it fails with `why`
  // (e.g. a vector quantity named without a component).
  void refuse(const std::string& name, const std::string& why);
  const std::string* refusal(const std::string& name) const;

 private:
  std::vector<std::string> names_;
  std::vector<VarRef> refs_;
  std::unordered_map<std::string, std::size_t> index_;  // name → first entry
  std::vector<std::pair<std::string, std::string>> refused_;
};

enum class Op : unsigned char {
  constant, variable, add, sub, mul, div, neg, pow, powi,
  sin, cos, tan, asin, acos, atan, exp, log, sqrt, abs, atan2, min, max
};
struct Instruction {
  Op op;
  VarKind kind = VarKind::parameter;  // for variable
  int index = 0;                      // variable index, or integer exponent for powi
  double value = 0;                   // for constant
};

// The arrays an expression reads. Any may be null if the expression does not use that kind.
template <class S>
struct Inputs {
  const S* parameters = nullptr;
  const S* coordinates = nullptr;
  const S* speeds = nullptr;
  const S* quantities = nullptr;
  S time = S(0);
};

// Scratch of Expression::gradient: per instruction its value, the partials of that value with
// respect to its (at most two) operands, and the adjoint. Sized once for the longest program; a
// gradient then allocates nothing.
template <class S>
struct Tape {
  std::vector<S> value, partial_a, partial_b, adjoint;
  void resize(std::size_t n) { value.resize(n), partial_a.resize(n), partial_b.resize(n), adjoint.resize(n); }
  std::size_t size() const { return value.size(); }
};

class Expression {
 public:
  static constexpr int kMaxStack = 32;

  Expression() = default;
  explicit Expression(double constant);

  const std::string& text() const { return text_; }
  // Where the expression was written (file:line:column) and its key path, for messages about
  // its value found after compilation (e.g. a derived parameter that evaluates to inf).
  const SourceLocation& where() const { return where_; }
  const std::string& key() const { return key_; }
  bool is_constant() const { return !uses_parameters_ && !uses_state_; }
  bool uses_parameters() const { return uses_parameters_; }
  // True if it reads t, a coordinate or a speed (must be evaluated every right-hand side).
  bool uses_state() const { return uses_state_; }
  // Value when is_constant().
  double constant_value() const { return code_.empty() ? 0.0 : code_[0].value; }
  // Whether it reads variable `index` of `kind` (e.g. coordinate 3).
  bool uses(VarKind kind, int index) const;
  // Whether it reads any variable of `kind`.
  bool uses_any(VarKind kind) const;
  // The indices of the variables of `kind` it reads (each once, in first-use order).
  std::vector<int> variables(VarKind kind) const;

  template <class S>
  S evaluate(const Inputs<S>& in) const;
  // The value (the same bits as evaluate) and its derivatives with respect to the coordinates
  // and time, from one forward sweep that records each instruction's local partials and one
  // reverse sweep of adjoints: the cost of a few evaluations however many coordinates it reads.
  // Adds ∂g/∂q_i to d_coordinates[i] for each coordinate i it reads (the caller zeroes them) and
  // sets d_time. tape.size() ≥ size().
  template <class S>
  S gradient(const Inputs<S>& in, Tape<S>& tape, S* d_coordinates, S& d_time) const;
  // Number of instructions (the tape a gradient needs).
  std::size_t size() const { return code_.size(); }

 private:
  friend Expression compile(const std::string&, const NameTable&, const SourceLocation&,
                            const std::string&);
  std::string text_;
  SourceLocation where_;
  std::string key_;
  std::vector<Instruction> code_;
  // Per instruction, the instructions whose values are its operands (−1: none): fixed by the
  // program, so the gradient's sweeps read them instead of replaying the stack.
  std::vector<std::array<int, 2>> operands_;
  bool uses_parameters_ = false;
  bool uses_state_ = false;
};

// Parses `text`. Errors are InputError naming `where`/`key` and the position in the text.
Expression compile(const std::string& text, const NameTable& names, const SourceLocation& where,
                   const std::string& key);

// ---- evaluation (header: inlined into the hot loops, no allocation) ----
template <class S>
S Expression::evaluate(const Inputs<S>& in) const {
  using std::abs, std::atan2, std::cos, std::exp, std::log, std::sin, std::sqrt, std::tan,
      std::asin, std::acos, std::atan, std::pow;
  // Slots are constructed when pushed: a default-constructed dual number zeroes its value and
  // tangents, which for the nested multi-tangent types costs more than the expression itself.
  union Slot {
    Slot() {}  // NOLINT: deliberately leaves x unconstructed
    S x;
  };
  static_assert(std::is_trivially_destructible_v<S>);
  if (code_.empty()) return S(0);
  std::array<Slot, kMaxStack> slots;
  int sp = 0;
  auto push = [&](const S& x) { std::construct_at(&slots[sp++].x, x); };
  auto st = [&](int i) -> S& { return slots[i].x; };
  for (const Instruction& ins : code_) {
    switch (ins.op) {
      case Op::constant: push(S(ins.value)); break;
      case Op::variable:
        switch (ins.kind) {
          case VarKind::parameter: push(in.parameters[ins.index]); break;
          case VarKind::time: push(in.time); break;
          case VarKind::coordinate: push(in.coordinates[ins.index]); break;
          case VarKind::speed: push(in.speeds[ins.index]); break;
          case VarKind::quantity: push(in.quantities[ins.index]); break;
        }
        break;
      case Op::add: --sp; st(sp - 1) = st(sp - 1) + st(sp); break;
      case Op::sub: --sp; st(sp - 1) = st(sp - 1) - st(sp); break;
      case Op::mul: --sp; st(sp - 1) = st(sp - 1) * st(sp); break;
      case Op::div: --sp; st(sp - 1) = st(sp - 1) / st(sp); break;
      case Op::pow: --sp; st(sp - 1) = pow(st(sp - 1), st(sp)); break;
      case Op::atan2: --sp; st(sp - 1) = atan2(st(sp - 1), st(sp)); break;
      case Op::min: --sp; st(sp - 1) = st(sp) < st(sp - 1) ? st(sp) : st(sp - 1); break;
      case Op::max: --sp; st(sp - 1) = st(sp - 1) < st(sp) ? st(sp) : st(sp - 1); break;
      case Op::neg: st(sp - 1) = -st(sp - 1); break;
      case Op::powi: {
        // Integer powers by repeated multiplication: exact for negative bases and for Dual.
        const S base = st(sp - 1);
        int n = ins.index < 0 ? -ins.index : ins.index;
        S r = S(1);
        for (int i = 0; i < n; ++i) r = r * base;
        st(sp - 1) = ins.index < 0 ? S(1) / r : r;
        break;
      }
      case Op::sin: st(sp - 1) = sin(st(sp - 1)); break;
      case Op::cos: st(sp - 1) = cos(st(sp - 1)); break;
      case Op::tan: st(sp - 1) = tan(st(sp - 1)); break;
      case Op::asin: st(sp - 1) = asin(st(sp - 1)); break;
      case Op::acos: st(sp - 1) = acos(st(sp - 1)); break;
      case Op::atan: st(sp - 1) = atan(st(sp - 1)); break;
      case Op::exp: st(sp - 1) = exp(st(sp - 1)); break;
      case Op::log: st(sp - 1) = log(st(sp - 1)); break;
      case Op::sqrt: st(sp - 1) = sqrt(st(sp - 1)); break;
      case Op::abs: st(sp - 1) = abs(st(sp - 1)); break;
    }
  }
  return st(0);
}

// sin x and cos x; the dual numbers overload it (math::sin_cos, found by argument-dependent
// lookup) to take the value's sine and cosine once.
template <class S>
void sin_cos(const S& x, S& s, S& c) {
  using std::cos, std::sin;
  s = sin(x), c = cos(x);
}

template <class S>
S Expression::gradient(const Inputs<S>& in, Tape<S>& tape, S* d_coordinates, S& d_time) const {
  using std::abs, std::atan2, std::exp, std::log, std::sqrt, std::tan, std::asin, std::acos, std::atan, std::pow;
  d_time = S(0);
  const int n = static_cast<int>(code_.size());
  if (n == 0) return S(0);
  assert(tape.size() >= code_.size());
  S* val = tape.value.data();
  S* pa = tape.partial_a.data();
  S* pb = tape.partial_b.data();
  const std::array<int, 2>* arg = operands_.data();
  // Forward: the operations of evaluate in the same order (the same value bits).
  for (int i = 0; i < n; ++i) {
    const Instruction& ins = code_[static_cast<std::size_t>(i)];
    const auto [a, b] = arg[i];
    switch (ins.op) {
      case Op::constant: val[i] = S(ins.value); break;
      case Op::variable:
        switch (ins.kind) {
          case VarKind::parameter: val[i] = in.parameters[ins.index]; break;
          case VarKind::time: val[i] = in.time; break;
          case VarKind::coordinate: val[i] = in.coordinates[ins.index]; break;
          case VarKind::speed: val[i] = in.speeds[ins.index]; break;
          case VarKind::quantity: val[i] = in.quantities[ins.index]; break;
        }
        break;
      case Op::add: val[i] = val[a] + val[b]; break;
      case Op::sub: val[i] = val[a] - val[b]; break;
      case Op::mul: val[i] = val[a] * val[b]; break;
      case Op::div: val[i] = val[a] / val[b]; break;
      case Op::pow:
        val[i] = pow(val[a], val[b]);
        pa[i] = val[b] * pow(val[a], val[b] - S(1));
        pb[i] = S(0) < val[a] ? val[i] * log(val[a]) : S(0);  // as the dual numbers' pow
        break;
      case Op::atan2: {
        val[i] = atan2(val[a], val[b]);
        const S r2 = val[b] * val[b] + val[a] * val[a];
        pa[i] = val[b] / r2;
        pb[i] = -val[a] / r2;
        break;
      }
      case Op::min: val[i] = val[b] < val[a] ? val[b] : val[a]; break;
      case Op::max: val[i] = val[a] < val[b] ? val[b] : val[a]; break;
      case Op::neg: val[i] = -val[a]; break;
      case Op::powi: {
        // As evaluate: repeated multiplication; the partial k x^(k−1) (k = ins.index) likewise.
        const S x = val[a];
        const int k = ins.index < 0 ? -ins.index : ins.index;
        S r = S(1), r_less = S(1);
        for (int j = 0; j < k; ++j) {
          if (j + 1 < k) r_less = r_less * x;
          r = r * x;
        }
        if (k == 0) {
          val[i] = ins.index < 0 ? S(1) / r : r;
          pa[i] = S(0);
        } else if (ins.index < 0) {
          val[i] = S(1) / r;
          pa[i] = S(ins.index) * r_less * val[i] * val[i];  // −k x^(k−1) / x^(2k)
        } else {
          val[i] = r;
          pa[i] = S(k) * r_less;
        }
        break;
      }
      case Op::sin: sin_cos(val[a], val[i], pa[i]); break;
      case Op::cos:
        sin_cos(val[a], pa[i], val[i]);
        pa[i] = -pa[i];
        break;
      case Op::tan: val[i] = tan(val[a]), pa[i] = S(1) + val[i] * val[i]; break;
      case Op::asin: val[i] = asin(val[a]), pa[i] = S(1) / sqrt(S(1) - val[a] * val[a]); break;
      case Op::acos: val[i] = acos(val[a]), pa[i] = S(-1) / sqrt(S(1) - val[a] * val[a]); break;
      case Op::atan: val[i] = atan(val[a]), pa[i] = S(1) / (S(1) + val[a] * val[a]); break;
      case Op::exp: val[i] = exp(val[a]), pa[i] = val[i]; break;
      case Op::log: val[i] = log(val[a]), pa[i] = S(1) / val[a]; break;
      case Op::sqrt:  // a zero derivative at 0, as the dual numbers' sqrt
        val[i] = sqrt(val[a]), pa[i] = S(0) < val[i] ? S(0.5) / val[i] : S(0);
        break;
      case Op::abs: val[i] = abs(val[a]), pa[i] = val[a] < S(0) ? S(-1) : S(1); break;
    }
  }
  // Reverse: adjoints from the result back to the variables.
  S* adj = tape.adjoint.data();
  for (int i = 0; i < n; ++i) adj[i] = S(0);
  adj[n - 1] = S(1);
  for (int i = n - 1; i >= 0; --i) {
    const Instruction& ins = code_[static_cast<std::size_t>(i)];
    const S& w = adj[i];
    const auto [a, b] = arg[i];
    switch (ins.op) {
      case Op::constant: break;
      case Op::variable:
        if (ins.kind == VarKind::coordinate) d_coordinates[ins.index] += w;
        else if (ins.kind == VarKind::time) d_time += w;
        break;
      case Op::add: adj[a] += w, adj[b] += w; break;
      case Op::sub: adj[a] += w, adj[b] -= w; break;
      case Op::neg: adj[a] -= w; break;
      case Op::mul: adj[a] += w * val[b], adj[b] += w * val[a]; break;
      case Op::div: {
        const S wb = w / val[b];
        adj[a] += wb;
        adj[b] -= wb * val[i];
        break;
      }
      case Op::pow:
      case Op::atan2: adj[a] += w * pa[i], adj[b] += w * pb[i]; break;
      case Op::min: adj[val[b] < val[a] ? b : a] += w; break;
      case Op::max: adj[val[a] < val[b] ? b : a] += w; break;
      default: adj[a] += w * pa[i]; break;  // the unary functions and powi
    }
  }
  return val[n - 1];
}

}  // namespace kanesens::model::expr
