#include "plc/debug/condition_code.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "plc/iec_literal.hpp"

namespace plc::debug {

namespace {

using Op = ConditionCode::Op;

// Recursive-descent parser emitting postfix code.
class ConditionParser {
 public:
  ConditionParser(std::string_view text, const ConditionResolver& resolve, ConditionCode& c)
      : s_(text), resolve_(resolve), c_(c) {}

  bool parse(std::string& error) {
    next();
    if (!expr_or()) {
      error = err_;
      return false;
    }
    if (tok_.kind != Tok::End) {
      error = "unexpected '" + tok_.text + "' at column " + std::to_string(tok_.pos + 1);
      return false;
    }
    return true;
  }

 private:
  enum class Tok { End, Ident, Number, Op, LParen, RParen };
  struct Token {
    Tok kind = Tok::End;
    std::string text;
    std::size_t pos = 0;
  };

  static std::string upper(std::string s) {
    for (char& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    return s;
  }

  void next() {
    while (p_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[p_]))) ++p_;
    tok_ = {};
    tok_.pos = p_;
    if (p_ >= s_.size()) return;
    const char ch = s_[p_];
    auto ident_char = [](char x) {
      return std::isalnum(static_cast<unsigned char>(x)) || x == '_' || x == '.' || x == '[' ||
             x == ']' || x == '#' || x == '%';
    };
    if (ch == '(') {
      tok_ = {Tok::LParen, "(", p_++};
      return;
    }
    if (ch == ')') {
      tok_ = {Tok::RParen, ")", p_++};
      return;
    }
    if (std::isdigit(static_cast<unsigned char>(ch))) {
      std::size_t q = p_;
      while (q < s_.size() &&
             (std::isalnum(static_cast<unsigned char>(s_[q])) || s_[q] == '#' || s_[q] == '_' ||
              s_[q] == '.' ||
              ((s_[q] == '+' || s_[q] == '-') && q > p_ && (s_[q - 1] == 'e' || s_[q - 1] == 'E'))))
        ++q;
      tok_ = {Tok::Number, std::string(s_.substr(p_, q - p_)), p_};
      p_ = q;
      return;
    }
    if (std::isalpha(static_cast<unsigned char>(ch)) || ch == '_' || ch == '%') {
      std::size_t q = p_;
      while (q < s_.size() && (ident_char(s_[q]) || (s_[q] == '-' && q > p_ && s_[q - 1] == '#')))
        ++q;
      tok_ = {Tok::Ident, std::string(s_.substr(p_, q - p_)), p_};
      p_ = q;
      const std::string u = upper(tok_.text);
      if (u == "AND" || u == "OR" || u == "XOR" || u == "NOT" || u == "MOD")
        tok_ = {Tok::Op, u, tok_.pos};
      return;
    }
    static const char* ops[] = {"<>", "<=", ">=", "=", "<", ">", "+", "-", "*", "/", "&"};
    for (const char* op : ops) {
      const std::string_view o(op);
      if (s_.substr(p_, o.size()) == o) {
        tok_ = {Tok::Op, std::string(o == "&" ? "AND" : o), p_};
        p_ += o.size();
        return;
      }
    }
    tok_ = {Tok::Op, std::string(1, ch), p_};
    ++p_;
  }

  bool fail(const std::string& m) {
    if (err_.empty()) err_ = m;
    return false;
  }
  // One level of '(', NOT or unary '-': each recurses, so the depth is
  // bounded here rather than by the thread's stack.
  struct Nest {
    explicit Nest(int& d) : depth(d) { ++depth; }
    ~Nest() { --depth; }
    Nest(const Nest&) = delete;
    Nest& operator=(const Nest&) = delete;
    int& depth;
  };
  bool too_deep(const Token& t) {
    return fail("condition nested too deeply at column " + std::to_string(t.pos + 1) +
                " (at most " + std::to_string(ConditionCode::kMaxNesting) +
                " levels of parentheses, NOT and unary '-')");
  }
  bool emit(Op op, std::uint16_t index = 0) {
    if (c_.code.size() >= ConditionCode::kMaxInstrs)
      return fail("condition too long (more than " + std::to_string(ConditionCode::kMaxInstrs) +
                  " operators and operands)");
    c_.code.push_back({op, index});
    return true;
  }
  bool is_op(const char* o) const { return tok_.kind == Tok::Op && tok_.text == o; }

  bool expr_or() {
    if (!expr_xor()) return false;
    while (is_op("OR")) {
      next();
      if (!expr_xor() || !emit(Op::Or)) return false;
    }
    return true;
  }
  bool expr_xor() {
    if (!expr_and()) return false;
    while (is_op("XOR")) {
      next();
      if (!expr_and() || !emit(Op::Xor)) return false;
    }
    return true;
  }
  bool expr_and() {
    if (!expr_not()) return false;
    while (is_op("AND")) {
      next();
      if (!expr_not() || !emit(Op::And)) return false;
    }
    return true;
  }
  bool expr_not() {
    if (is_op("NOT")) {
      const Nest nest(depth_);
      if (depth_ > ConditionCode::kMaxNesting) return too_deep(tok_);
      next();
      return expr_not() && emit(Op::Not);
    }
    return compare();
  }
  bool compare() {
    if (!sum()) return false;
    static const std::pair<const char*, Op> cmps[] = {{"=", Op::Eq}, {"<>", Op::Ne},
                                                      {"<", Op::Lt}, {"<=", Op::Le},
                                                      {">", Op::Gt}, {">=", Op::Ge}};
    for (const auto& [t, op] : cmps) {
      if (is_op(t)) {
        next();
        return sum() && emit(op);
      }
    }
    return true;
  }
  bool sum() {
    if (!term()) return false;
    while (is_op("+") || is_op("-")) {
      const auto op = is_op("+") ? Op::Add : Op::Sub;
      next();
      if (!term() || !emit(op)) return false;
    }
    return true;
  }
  bool term() {
    if (!unary()) return false;
    while (is_op("*") || is_op("/") || is_op("MOD")) {
      const auto op = is_op("*") ? Op::Mul : is_op("/") ? Op::Div : Op::Mod;
      next();
      if (!unary() || !emit(op)) return false;
    }
    return true;
  }
  bool unary() {
    if (is_op("-")) {
      const Nest nest(depth_);
      if (depth_ > ConditionCode::kMaxNesting) return too_deep(tok_);
      next();
      return unary() && emit(Op::Neg);
    }
    return primary();
  }
  bool constant(Value v) {
    // Equal constants share one slot.
    auto it = std::find(c_.consts.begin(), c_.consts.end(), v);
    if (it == c_.consts.end()) {
      if (c_.consts.size() >= ConditionCode::kMaxConsts)
        return fail("condition has too many constants (more than " +
                    std::to_string(ConditionCode::kMaxConsts) + ")");
      c_.consts.push_back(v);
      it = c_.consts.end() - 1;
    }
    return emit(Op::Const, static_cast<std::uint16_t>(it - c_.consts.begin()));
  }
  bool primary() {
    const Token t = tok_;
    if (t.kind == Tok::LParen) {
      const Nest nest(depth_);
      if (depth_ > ConditionCode::kMaxNesting) return too_deep(t);
      next();
      if (!expr_or()) return false;
      if (tok_.kind != Tok::RParen)
        return fail("missing ')' at column " + std::to_string(tok_.pos + 1));
      next();
      return true;
    }
    if (t.kind == Tok::Number) {
      next();
      if (auto i = parse_iec_integer(t.text)) return constant({false, *i, 0});
      if (auto d = parse_iec_real(t.text)) return constant({true, 0, *d});
      return fail("'" + t.text + "' is not a number");
    }
    if (t.kind == Tok::Ident) {
      next();
      const std::string u = upper(t.text);
      if (u == "TRUE") return constant({false, 1, 0});
      if (u == "FALSE") return constant({false, 0, 0});
      if (u.rfind("T#", 0) == 0 || u.rfind("TIME#", 0) == 0) {
        auto tm = parse_iec_time(t.text);
        if (!tm) return fail("'" + t.text + "' is not a duration");
        return constant({false, tm->count(), 0});
      }
      if (t.text[0] != '%')
        if (auto typed = parse_iec_integer(t.text)) return constant({false, *typed, 0});  // INT#5
      if (operands_ >= ConditionCode::kMaxOperands)
        return fail("condition reads too many variables (more than " +
                    std::to_string(ConditionCode::kMaxOperands) + ")");
      std::string why;
      const auto operand = resolve_(t.text, why);
      if (!operand) return fail(why.empty() ? "unknown variable '" + t.text + "'" : why);
      ++operands_;
      return emit(Op::Var, *operand);
    }
    if (t.kind == Tok::End) return fail("incomplete condition");
    return fail("unexpected '" + t.text + "' at column " + std::to_string(t.pos + 1));
  }

  std::string_view s_;
  std::size_t p_ = 0;
  Token tok_;
  std::string err_;
  int depth_ = 0;  // open '(' / NOT / unary '-' levels
  std::size_t operands_ = 0;
  const ConditionResolver& resolve_;
  ConditionCode& c_;
};

bool is_unary(Op op) { return op == Op::Neg || op == Op::Not; }

// LINT arithmetic as a PLC's 64-bit integer unit does it: two's-complement
// wrap-around, computed on the unsigned bit pattern so that no overflow is
// undefined behaviour.
std::int64_t wrap(std::uint64_t x) { return static_cast<std::int64_t>(x); }
std::uint64_t bits(std::int64_t x) { return static_cast<std::uint64_t>(x); }

// Division and MOD never trap: by zero they give 0, and the one quotient
// that does not fit, LINT_MIN / -1, wraps to LINT_MIN (its remainder is 0).
std::int64_t int_div(std::int64_t a, std::int64_t b) {
  if (b == 0) return 0;
  if (b == -1) return wrap(0 - bits(a));
  return a / b;
}
std::int64_t int_mod(std::int64_t a, std::int64_t b) {
  if (b == 0 || b == -1) return 0;
  return a % b;
}

enum class Order { Less, Equal, Greater, Unordered };

template <class T>
Order order_of(T a, T b) {
  return a < b ? Order::Less : b < a ? Order::Greater : a == b ? Order::Equal : Order::Unordered;
}

// An integer against a real, exactly: converting the integer to double
// would round above 2^53 (and make 2^63-1 equal 2^63); converting an
// out-of-range double to an integer would be undefined.
Order order_int_real(std::int64_t i, double d) {
  if (std::isnan(d)) return Order::Unordered;
  constexpr double kTwo63 = 9223372036854775808.0;
  if (d >= kTwo63) return Order::Less;
  if (d < -kTwo63) return Order::Greater;
  const double whole = std::trunc(d);  // in [-2^63, 2^63): fits
  const auto w = static_cast<std::int64_t>(whole);
  if (i != w) return i < w ? Order::Less : Order::Greater;
  const double frac = d - whole;
  return frac > 0 ? Order::Less : frac < 0 ? Order::Greater : Order::Equal;
}

Order compare(const Value& a, const Value& b) {
  if (!a.real && !b.real) return order_of(a.i, b.i);
  if (a.real && b.real) return order_of(a.d, b.d);
  if (!a.real) return order_int_real(a.i, b.d);
  const Order o = order_int_real(b.i, a.d);  // the mirror image
  return o == Order::Less ? Order::Greater : o == Order::Greater ? Order::Less : o;
}

// Precedence levels of the grammar, loosest first (to_text).
enum Level { kOr = 1, kXor, kAnd, kNot, kCompare, kSum, kTerm, kUnary, kPrimary };

Level level_of(Op op) {
  switch (op) {
    case Op::Or:
      return kOr;
    case Op::Xor:
      return kXor;
    case Op::And:
      return kAnd;
    case Op::Not:
      return kNot;
    case Op::Eq:
    case Op::Ne:
    case Op::Lt:
    case Op::Le:
    case Op::Gt:
    case Op::Ge:
      return kCompare;
    case Op::Add:
    case Op::Sub:
      return kSum;
    case Op::Mul:
    case Op::Div:
    case Op::Mod:
      return kTerm;
    case Op::Neg:
      return kUnary;
    default:
      return kPrimary;
  }
}

const char* symbol_of(Op op) {
  static const char* const names[] = {"",   "",  "+",  "-", "*",  "/",   "MOD", "-",   "=",
                                      "<>", "<", "<=", ">", ">=", "AND", "OR",  "XOR", "NOT"};
  return names[std::size_t(op)];
}

std::string constant_text(const Value& v) {
  // A negative integer (a negative duration, INT#-5) as a typed literal,
  // which the parser reads back as the same constant (not as unary minus).
  if (!v.real) return v.i < 0 ? "LINT#" + std::to_string(v.i) : std::to_string(v.i);
  // Only code from outside holds these; listed, never read back.
  if (std::isnan(v.d)) return "NaN";
  if (std::isinf(v.d)) return v.d > 0 ? "Inf" : "-Inf";
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v.d);
  std::string s = b;
  // A real must read back as a real, not as an integer.
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

std::optional<ConditionCode> compile_condition(std::string_view text,
                                               const ConditionResolver& resolve,
                                               std::string& error) {
  ConditionCode c;
  ConditionParser p(text, resolve, c);
  if (!p.parse(error)) return std::nullopt;
  // The stack depth, checked once so that evaluate() can use a fixed array.
  int depth = 0, max_depth = 0;
  for (const auto& in : c.code) {
    if (in.op == Op::Const || in.op == Op::Var)
      ++depth;
    else if (!is_unary(in.op))
      --depth;
    max_depth = std::max(max_depth, depth);
  }
  if (max_depth > ConditionCode::kMaxStack) {
    error = "condition too deeply nested (more than " + std::to_string(ConditionCode::kMaxStack) +
            " operands pending)";
    return std::nullopt;
  }
  return c;
}

std::string validate(const ConditionCode& c, std::size_t operands) {
  if (c.code.empty()) return "empty code";
  if (c.code.size() > ConditionCode::kMaxInstrs)
    return "code of " + std::to_string(c.code.size()) + " instructions (at most " +
           std::to_string(ConditionCode::kMaxInstrs) + ")";
  if (c.consts.size() > ConditionCode::kMaxConsts)
    return std::to_string(c.consts.size()) + " constants (at most " +
           std::to_string(ConditionCode::kMaxConsts) + ")";
  if (operands > ConditionCode::kMaxOperands)
    return std::to_string(operands) + " operands (at most " +
           std::to_string(ConditionCode::kMaxOperands) + ")";
  int depth = 0;
  for (std::size_t k = 0; k < c.code.size(); ++k) {
    const auto& in = c.code[k];
    const std::string at = " at instruction " + std::to_string(k);
    if (std::uint8_t(in.op) >= ConditionCode::kOps)
      return "unknown op code " + std::to_string(int(in.op)) + at;
    if (in.op == Op::Const) {
      if (in.index >= c.consts.size()) return "constant index out of range" + at;
      ++depth;
    } else if (in.op == Op::Var) {
      if (in.index >= operands) return "operand index out of range" + at;
      ++depth;
    } else if (is_unary(in.op)) {
      if (depth < 1) return "operator without its operand" + at;
    } else {
      if (depth < 2) return "operator without its two operands" + at;
      --depth;
    }
    if (depth > ConditionCode::kMaxStack)
      return "more than " + std::to_string(ConditionCode::kMaxStack) + " operands pending" + at;
  }
  if (depth != 1) return std::to_string(depth) + " values left at the end (one expected)";
  return {};
}

std::string to_text(const ConditionCode& c,
                    const std::function<std::string(std::uint16_t)>& name_of) {
  struct Part {
    std::string text;
    Level level;
  };
  std::vector<Part> st;
  auto wrapped = [](const Part& p, bool paren) { return paren ? "(" + p.text + ")" : p.text; };
  for (const auto& in : c.code) {
    if (in.op == Op::Const) {
      const Value& v = c.consts[in.index];
      // A negative real (only code from outside has one) reads as unary minus.
      const bool neg = v.real && std::signbit(v.d) && !std::isnan(v.d);
      st.push_back({constant_text(v), neg ? kUnary : kPrimary});
    } else if (in.op == Op::Var) {
      st.push_back({name_of(in.index), kPrimary});
    } else if (is_unary(in.op)) {
      Part& a = st.back();
      if (in.op == Op::Not) {
        a = {"NOT " + wrapped(a, a.level < kNot), kNot};
      } else {
        a = {"-" + wrapped(a, a.level < kUnary), kUnary};
      }
    } else {
      Part b = std::move(st.back());
      st.pop_back();
      Part& a = st.back();
      const Level l = level_of(in.op);
      // Left-associative; a comparison takes sums on both sides.
      a = {wrapped(a, a.level < l || (l == kCompare && a.level == kCompare)) + " " +
               symbol_of(in.op) + " " + wrapped(b, b.level <= l),
           l};
    }
  }
  return st.empty() ? std::string() : st.front().text;
}

Value apply_unary(Op op, const Value& a) {
  if (op == Op::Not) return {false, a.truthy() ? 0 : 1, 0};
  if (a.real) return {true, 0, -a.d};
  return {false, wrap(0 - bits(a.i)), 0};
}

Value apply_binary(Op op, const Value& a, const Value& b) {
  const bool real = a.real || b.real;
  const double x = a.as_real(), y = b.as_real();
  // IEEE 754 for REAL/LREAL (inf and NaN are values, never traps), except
  // that division and MOD by zero give 0 like the integers.
  switch (op) {
    case Op::Add:
      return real ? Value{true, 0, x + y} : Value{false, wrap(bits(a.i) + bits(b.i)), 0};
    case Op::Sub:
      return real ? Value{true, 0, x - y} : Value{false, wrap(bits(a.i) - bits(b.i)), 0};
    case Op::Mul:
      return real ? Value{true, 0, x * y} : Value{false, wrap(bits(a.i) * bits(b.i)), 0};
    case Op::Div:
      return real ? Value{true, 0, y == 0 ? 0.0 : x / y} : Value{false, int_div(a.i, b.i), 0};
    case Op::Mod:
      return real ? Value{true, 0, y == 0 ? 0.0 : std::fmod(x, y)}
                  : Value{false, int_mod(a.i, b.i), 0};
    case Op::Eq:
      return {false, compare(a, b) == Order::Equal, 0};
    case Op::Ne:
      return {false, compare(a, b) != Order::Equal, 0};
    case Op::Lt:
      return {false, compare(a, b) == Order::Less, 0};
    case Op::Le: {
      const Order o = compare(a, b);
      return {false, o == Order::Less || o == Order::Equal, 0};
    }
    case Op::Gt:
      return {false, compare(a, b) == Order::Greater, 0};
    case Op::Ge: {
      const Order o = compare(a, b);
      return {false, o == Order::Greater || o == Order::Equal, 0};
    }
    case Op::And:
      return {false, a.truthy() && b.truthy(), 0};
    case Op::Or:
      return {false, a.truthy() || b.truthy(), 0};
    case Op::Xor:
      return {false, a.truthy() != b.truthy(), 0};
    default:
      return a;
  }
}

}  // namespace plc::debug
