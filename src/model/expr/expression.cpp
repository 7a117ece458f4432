// Recursive-descent parser for scene expressions, emitting a postfix program.
//   expr    := term (('+'|'-') term)*
//   term    := unary (('*'|'/') unary)*
//   unary   := ('-'|'+') unary | power
//   power   := primary (('^'|'**') unary)?       right-associative; -x^2 = -(x^2)
//   primary := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
//   name    := ident ('.' ident)*                 e.g. m2, elbow.q, ball.wx
#include "model/expr/expression.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>

#include "util/did_you_mean.hpp"

namespace kanesens::model::expr {
namespace {

struct FunctionInfo {
  Op op;
  int arity;
};
const std::map<std::string, FunctionInfo>& functions() {
  static const std::map<std::string, FunctionInfo> table = {
      {"sin", {Op::sin, 1}},   {"cos", {Op::cos, 1}},   {"tan", {Op::tan, 1}},
      {"asin", {Op::asin, 1}}, {"acos", {Op::acos, 1}}, {"atan", {Op::atan, 1}},
      {"exp", {Op::exp, 1}},   {"log", {Op::log, 1}},   {"sqrt", {Op::sqrt, 1}},
      {"abs", {Op::abs, 1}},   {"atan2", {Op::atan2, 2}}, {"min", {Op::min, 2}},
      {"max", {Op::max, 2}}};
  return table;
}

class Parser {
 public:
  Parser(const std::string& text, const NameTable& names, const SourceLocation& where,
         const std::string& key)
      : s_(text), names_(names), where_(where), key_(key) {}

  std::vector<Instruction> parse(bool& uses_parameters, bool& uses_state) {
    skip_space();
    if (pos_ >= s_.size()) fail("empty expression");
    parse_expr();
    skip_space();
    if (pos_ < s_.size()) fail(std::string("unexpected '") + s_[pos_] + "'");
    uses_parameters = uses_parameters_;
    uses_state = uses_state_;
    return std::move(code_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(where_, key_,
                     what + " at position " + std::to_string(pos_ + 1) + " of expression '" + s_ + "'");
  }
  // A parameter-free part folds to inf or NaN (1/0, log(0), 1e300*1e300): the whole expression
  // could never be finite, so it is an input error rather than a NaN found at run time.
  [[noreturn]] void fail_constant(const std::string& what) const {
    throw InputError(where_, key_, what + " in expression '" + s_ + "'");
  }
  // Recursion guard: parentheses, unary signs and function calls nest the descent; a limit
  // keeps hostile input ("((((...", "----...1") from exhausting the stack.
  struct Nest {
    explicit Nest(Parser& p) : p_(p) {
      if (++p_.nesting_ > kMaxNesting) p_.fail("expression nested too deeply");
    }
    ~Nest() { --p_.nesting_; }
    Parser& p_;
  };
  static constexpr int kMaxNesting = 64;
  void skip_space() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool accept(const char* tok) {
    skip_space();
    const std::size_t n = std::char_traits<char>::length(tok);
    if (s_.compare(pos_, n, tok) == 0) {
      pos_ += n;
      return true;
    }
    return false;
  }
  void emit(Instruction ins, int stack_delta) {
    code_.push_back(ins);
    depth_ += stack_delta;
    max_depth_ = std::max(max_depth_, depth_);
    if (max_depth_ > Expression::kMaxStack) fail("expression nested too deeply");
  }
  void binary(Op op) {
    // Constant folding keeps parameter-free subexpressions cheap.
    const std::size_t n = code_.size();
    if (n >= 2 && code_[n - 1].op == Op::constant && code_[n - 2].op == Op::constant) {
      const double a = code_[n - 2].value, b = code_[n - 1].value;
      double r = 0;
      switch (op) {
        case Op::add: r = a + b; break;
        case Op::sub: r = a - b; break;
        case Op::mul: r = a * b; break;
        case Op::div: r = a / b; break;
        case Op::pow: r = std::pow(a, b); break;
        case Op::atan2: r = std::atan2(a, b); break;
        case Op::min: r = std::min(a, b); break;
        case Op::max: r = std::max(a, b); break;
        default: goto no_fold;
      }
      if (!std::isfinite(r)) fail_constant(op == Op::div && b == 0 ? "division by zero" : "a constant part is not finite (" + std::to_string(r) + ")");
      code_.pop_back();
      code_.back().value = r;
      --depth_;
      return;
    }
  no_fold:
    if (op == Op::pow && n >= 1 && code_[n - 1].op == Op::constant) {
      const double e = code_[n - 1].value;
      if (e == std::round(e) && std::abs(e) <= 16) {
        code_.pop_back();
        --depth_;
        emit({Op::powi, VarKind::parameter, static_cast<int>(e), 0}, 0);
        return;
      }
    }
    emit({op}, -1);
  }
  void unary_op(Op op) {
    if (!code_.empty() && code_.back().op == Op::constant) {
      double& v = code_.back().value;
      bool folded = true;
      switch (op) {
        case Op::neg: v = -v; break;
        case Op::sin: v = std::sin(v); break;
        case Op::cos: v = std::cos(v); break;
        case Op::tan: v = std::tan(v); break;
        case Op::asin: v = std::asin(v); break;
        case Op::acos: v = std::acos(v); break;
        case Op::atan: v = std::atan(v); break;
        case Op::exp: v = std::exp(v); break;
        case Op::log: v = std::log(v); break;
        case Op::sqrt: v = std::sqrt(v); break;
        case Op::abs: v = std::abs(v); break;
        default: folded = false; break;
      }
      if (folded) {
        if (!std::isfinite(v)) fail_constant("a constant part is not finite (" + std::to_string(v) + ")");
        return;
      }
    }
    emit({op}, 0);
  }

  void parse_expr() {
    Nest guard(*this);
    parse_term();
    for (;;) {
      if (accept("+")) { parse_term(); binary(Op::add); }
      else if (accept("-")) { parse_term(); binary(Op::sub); }
      else return;
    }
  }
  void parse_term() {
    parse_unary();
    for (;;) {
      skip_space();
      if (s_.compare(pos_, 2, "**") == 0) return;  // power, handled below
      if (accept("*")) { parse_unary(); binary(Op::mul); }
      else if (accept("/")) { parse_unary(); binary(Op::div); }
      else return;
    }
  }
  void parse_unary() {
    Nest guard(*this);
    if (accept("-")) { parse_unary(); unary_op(Op::neg); return; }
    if (accept("+")) { parse_unary(); return; }
    parse_power();
  }
  void parse_power() {
    parse_primary();
    if (accept("^") || accept("**")) {
      parse_unary();
      binary(Op::pow);
    }
  }
  void parse_primary() {
    skip_space();
    if (pos_ >= s_.size()) fail("expression ends early");
    const char c = s_[pos_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = s_.c_str() + pos_;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin) fail("bad number");
      if (!std::isfinite(v)) fail("number out of range (not a finite double)");
      pos_ += static_cast<std::size_t>(end - begin);
      emit({Op::constant, VarKind::parameter, 0, v}, 1);
      return;
    }
    if (accept("(")) {
      parse_expr();
      if (!accept(")")) fail("missing ')'");
      return;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const std::size_t start = pos_;
      std::string name = ident();
      while (pos_ < s_.size() && s_[pos_] == '.') {
        ++pos_;
        name.push_back('.');
        name.append(ident());
      }
      skip_space();
      if (pos_ < s_.size() && s_[pos_] == '(') {
        ++pos_;
        auto it = functions().find(name);
        if (it == functions().end()) {
          pos_ = start;
          std::vector<std::string> names;
          for (const auto& [n, f] : functions()) names.push_back(n);
          fail("unknown function '" + name + "'" + did_you_mean(name, names) +
               "; functions are: " + join_names(names));
        }
        for (int a = 0; a < it->second.arity; ++a) {
          if (a > 0 && !accept(",")) fail("'" + name + "' takes " + std::to_string(it->second.arity) + " arguments");
          parse_expr();
        }
        if (!accept(")")) fail("missing ')' after arguments of '" + name + "'");
        if (it->second.arity == 2) binary(it->second.op);
        else unary_op(it->second.op);
        return;
      }
      if (name == "pi") {
        emit({Op::constant, VarKind::parameter, 0, M_PI}, 1);
        return;
      }
      const auto ref = names_.find(name);
      if (!ref) {
        pos_ = start;
        if (const std::string* why = names_.refusal(name)) fail(*why);
        fail("unknown name '" + name + "'" + did_you_mean(name, names_.names()) +
             "; names allowed here: " + join_names(names_.names()));
      }
      if (ref->kind == VarKind::parameter) uses_parameters_ = true;
      else uses_state_ = true;
      emit({Op::variable, ref->kind, ref->index, 0}, 1);
      return;
    }
    fail(std::string("unexpected '") + c + "'");
  }
  std::string ident() {
    const std::size_t start = pos_;
    if (pos_ >= s_.size() || !(std::isalpha(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_'))
      fail("expected a name");
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_'))
      ++pos_;
    return s_.substr(start, pos_ - start);
  }

  const std::string& s_;
  const NameTable& names_;
  const SourceLocation& where_;
  const std::string& key_;
  std::size_t pos_ = 0;
  std::vector<Instruction> code_;
  int depth_ = 0, max_depth_ = 0, nesting_ = 0;
  bool uses_parameters_ = false, uses_state_ = false;
};

}  // namespace

Expression::Expression(double constant) : text_(std::to_string(constant)) {
  code_.push_back({Op::constant, VarKind::parameter, 0, constant});
  operands_.push_back({-1, -1});
}

namespace {
// Replays the program's stack with instruction indices: the operands of each instruction.
std::vector<std::array<int, 2>> operands_of(const std::vector<Instruction>& code) {
  std::vector<std::array<int, 2>> out(code.size(), {-1, -1});
  std::vector<int> stack;
  for (std::size_t i = 0; i < code.size(); ++i) {
    const Op op = code[i].op;
    if (op != Op::constant && op != Op::variable) {
      const bool binary = op == Op::add || op == Op::sub || op == Op::mul || op == Op::div || op == Op::pow ||
                          op == Op::atan2 || op == Op::min || op == Op::max;
      if (binary) out[i][1] = stack.back(), stack.pop_back();
      out[i][0] = stack.back(), stack.pop_back();
    }
    stack.push_back(static_cast<int>(i));
  }
  return out;
}
}  // namespace

void NameTable::add(const std::string& name, VarRef ref) {
  index_.emplace(name, names_.size());  // the first entry of a name wins, as before
  names_.push_back(name);
  refs_.push_back(ref);
}

void NameTable::refuse(const std::string& name, const std::string& why) {
  refused_.emplace_back(name, why);
}

const std::string* NameTable::refusal(const std::string& name) const {
  for (const auto& [n, why] : refused_)
    if (n == name) return &why;
  return nullptr;
}

std::vector<int> Expression::variables(VarKind kind) const {
  std::vector<int> out;
  for (const Instruction& ins : code_)
    if (ins.op == Op::variable && ins.kind == kind && std::find(out.begin(), out.end(), ins.index) == out.end())
      out.push_back(ins.index);
  return out;
}

std::optional<VarRef> NameTable::find(const std::string& name) const {
  const auto it = index_.find(name);
  if (it == index_.end()) return std::nullopt;
  return refs_[it->second];
}

bool Expression::uses(VarKind kind, int index) const {
  for (const Instruction& i : code_)
    if (i.op == Op::variable && i.kind == kind && i.index == index) return true;
  return false;
}

bool Expression::uses_any(VarKind kind) const {
  for (const Instruction& i : code_)
    if (i.op == Op::variable && i.kind == kind) return true;
  return false;
}

Expression compile(const std::string& text, const NameTable& names, const SourceLocation& where,
                   const std::string& key) {
  Expression e;
  e.text_ = text;
  e.where_ = where;
  e.key_ = key;
  Parser p(text, names, where, key);
  e.code_ = p.parse(e.uses_parameters_, e.uses_state_);
  e.operands_ = operands_of(e.code_);
  return e;
}

}  // namespace kanesens::model::expr
