#include "plc/debug/condition.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>

#include "plc/iec_literal.hpp"

namespace plc::debug {

namespace {

template <class T>
T load(const unsigned char* buf) {
  T x;
  std::memcpy(&x, buf, sizeof x);
  return x;
}

}  // namespace

Value read_value(const VarInfo& v) {
  alignas(8) unsigned char buf[16] = {};
  Value out;
  if (v.type == VarType::STRING) return out;  // strings compare as 0
  VarRegistry::read(v, buf);
  switch (v.type) {
    case VarType::BOOL:
      out.i = load<bool>(buf) ? 1 : 0;
      break;
    case VarType::SINT:
      out.i = load<std::int8_t>(buf);
      break;
    case VarType::INT:
      out.i = load<std::int16_t>(buf);
      break;
    case VarType::DINT:
      out.i = load<std::int32_t>(buf);
      break;
    case VarType::LINT:
    case VarType::TIME:
      out.i = load<std::int64_t>(buf);
      break;
    case VarType::USINT:
    case VarType::BYTE:
      out.i = load<std::uint8_t>(buf);
      break;
    case VarType::UINT:
    case VarType::WORD:
      out.i = load<std::uint16_t>(buf);
      break;
    case VarType::UDINT:
    case VarType::DWORD:
      out.i = load<std::uint32_t>(buf);
      break;
    case VarType::ULINT:
    case VarType::LWORD:
      // The bit pattern as a LINT (two's complement): values from 2^63 up
      // read as negative numbers, as a PLC's LINT view of the same 64 bits.
      out.i = static_cast<std::int64_t>(load<std::uint64_t>(buf));
      break;
    case VarType::REAL:
      out.real = true;
      out.d = load<float>(buf);
      break;
    case VarType::LREAL:
      out.real = true;
      out.d = load<double>(buf);
      break;
    case VarType::STRING:
      break;
  }
  return out;
}

// Recursive-descent parser emitting postfix code.
class ConditionParser {
 public:
  ConditionParser(std::string_view text, const VarRegistry& vars, io::ProcessImage& global,
                  io::ByteOrder order, Condition& c)
      : s_(text), vars_(vars), global_(global), order_(order), c_(c) {}

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
                " (at most " + std::to_string(Condition::kMaxNesting) +
                " levels of parentheses, NOT and unary '-')");
  }
  void emit(Condition::Op op, std::uint32_t index = 0) { c_.code_.push_back({op, index}); }
  bool is_op(const char* o) const { return tok_.kind == Tok::Op && tok_.text == o; }

  bool expr_or() {
    if (!expr_xor()) return false;
    while (is_op("OR")) {
      next();
      if (!expr_xor()) return false;
      emit(Condition::Op::Or);
    }
    return true;
  }
  bool expr_xor() {
    if (!expr_and()) return false;
    while (is_op("XOR")) {
      next();
      if (!expr_and()) return false;
      emit(Condition::Op::Xor);
    }
    return true;
  }
  bool expr_and() {
    if (!expr_not()) return false;
    while (is_op("AND")) {
      next();
      if (!expr_not()) return false;
      emit(Condition::Op::And);
    }
    return true;
  }
  bool expr_not() {
    if (is_op("NOT")) {
      const Nest nest(depth_);
      if (depth_ > Condition::kMaxNesting) return too_deep(tok_);
      next();
      if (!expr_not()) return false;
      emit(Condition::Op::Not);
      return true;
    }
    return compare();
  }
  bool compare() {
    if (!sum()) return false;
    static const std::pair<const char*, Condition::Op> cmps[] = {
        {"=", Condition::Op::Eq},  {"<>", Condition::Op::Ne}, {"<", Condition::Op::Lt},
        {"<=", Condition::Op::Le}, {">", Condition::Op::Gt},  {">=", Condition::Op::Ge}};
    for (const auto& [t, op] : cmps) {
      if (is_op(t)) {
        next();
        if (!sum()) return false;
        emit(op);
        return true;
      }
    }
    return true;
  }
  bool sum() {
    if (!term()) return false;
    while (is_op("+") || is_op("-")) {
      const auto op = is_op("+") ? Condition::Op::Add : Condition::Op::Sub;
      next();
      if (!term()) return false;
      emit(op);
    }
    return true;
  }
  bool term() {
    if (!unary()) return false;
    while (is_op("*") || is_op("/") || is_op("MOD")) {
      const auto op = is_op("*")   ? Condition::Op::Mul
                      : is_op("/") ? Condition::Op::Div
                                   : Condition::Op::Mod;
      next();
      if (!unary()) return false;
      emit(op);
    }
    return true;
  }
  bool unary() {
    if (is_op("-")) {
      const Nest nest(depth_);
      if (depth_ > Condition::kMaxNesting) return too_deep(tok_);
      next();
      if (!unary()) return false;
      emit(Condition::Op::Neg);
      return true;
    }
    return primary();
  }
  bool constant(Value v) {
    c_.consts_.push_back(v);
    emit(Condition::Op::Const, static_cast<std::uint32_t>(c_.consts_.size() - 1));
    return true;
  }
  bool primary() {
    const Token t = tok_;
    if (t.kind == Tok::LParen) {
      const Nest nest(depth_);
      if (depth_ > Condition::kMaxNesting) return too_deep(t);
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
      if (t.text[0] == '%') {
        auto r = io::parse_iec_address(t.text);
        if (!r.address) return fail(r.error);
        if (!global_.contains(*r.address)) return fail(t.text + " lies outside the image");
        VarInfo v;
        v.path = t.text;
        v.address = *r.address;
        v.image_ptr = global_.at(*r.address);
        v.order = order_;
        static const VarType types[] = {VarType::BOOL, VarType::BYTE, VarType::WORD, VarType::DWORD,
                                        VarType::LWORD};
        v.type = types[static_cast<int>(r.address->size)];
        c_.vars_.push_back(v);
        emit(Condition::Op::Var, static_cast<std::uint32_t>(c_.vars_.size() - 1));
        return true;
      }
      if (auto typed = parse_iec_integer(t.text)) return constant({false, *typed, 0});  // INT#5
      const VarInfo* v = vars_.find(t.text);
      if (!v) return fail("unknown variable '" + t.text + "'");
      if (v->type == VarType::STRING)
        return fail("'" + t.text + "' is a STRING; conditions compare numbers");
      if (c_.task_ < 0) c_.task_ = v->task;
      c_.vars_.push_back(*v);
      emit(Condition::Op::Var, static_cast<std::uint32_t>(c_.vars_.size() - 1));
      return true;
    }
    if (t.kind == Tok::End) return fail("incomplete condition");
    return fail("unexpected '" + t.text + "' at column " + std::to_string(t.pos + 1));
  }

  std::string_view s_;
  std::size_t p_ = 0;
  Token tok_;
  std::string err_;
  int depth_ = 0;  // open '(' / NOT / unary '-' levels
  const VarRegistry& vars_;
  io::ProcessImage& global_;
  io::ByteOrder order_;
  Condition& c_;
};

std::optional<Condition> Condition::compile(std::string_view text, const VarRegistry& vars,
                                            io::ProcessImage& global, io::ByteOrder order,
                                            std::string& error) {
  Condition c;
  c.text_ = std::string(text);
  ConditionParser p(text, vars, global, order, c);
  if (!p.parse(error)) return std::nullopt;
  // Check the stack depth once so evaluate() can use a fixed array.
  int depth = 0, max_depth = 0;
  for (const Instr& in : c.code_) {
    if (in.op == Op::Const || in.op == Op::Var)
      ++depth;
    else if (in.op != Op::Neg && in.op != Op::Not)
      --depth;
    max_depth = std::max(max_depth, depth);
  }
  if (max_depth > kMaxOperands) {
    error = "condition too deeply nested (more than " + std::to_string(kMaxOperands) +
            " operands pending)";
    return std::nullopt;
  }
  return c;
}

std::vector<const VarInfo*> Condition::variables() const {
  std::vector<const VarInfo*> out;
  for (const VarInfo& v : vars_) out.push_back(&v);
  return out;
}

bool Condition::reads_global() const {
  return std::any_of(vars_.begin(), vars_.end(), [](const VarInfo& v) { return v.task < 0; });
}

namespace {

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

}  // namespace

Value Condition::evaluate() const {
  std::array<Value, kMaxOperands> st;
  int sp = 0;
  for (const Instr& in : code_) {
    switch (in.op) {
      case Op::Const:
        st[sp++] = consts_[in.index];
        break;
      case Op::Var:
        st[sp++] = read_value(vars_[in.index]);
        break;
      case Op::Neg: {
        Value& a = st[sp - 1];
        if (a.real)
          a.d = -a.d;
        else
          a.i = wrap(0 - bits(a.i));
        break;
      }
      case Op::Not:
        st[sp - 1] = {false, st[sp - 1].truthy() ? 0 : 1, 0};
        break;
      default: {
        const Value b = st[--sp];
        Value& a = st[sp - 1];
        const bool real = a.real || b.real;
        const double x = a.as_real(), y = b.as_real();
        // IEEE 754 for REAL/LREAL (inf and NaN are values, never traps),
        // except that division and MOD by zero give 0 like the integers.
        switch (in.op) {
          case Op::Add:
            a = real ? Value{true, 0, x + y} : Value{false, wrap(bits(a.i) + bits(b.i)), 0};
            break;
          case Op::Sub:
            a = real ? Value{true, 0, x - y} : Value{false, wrap(bits(a.i) - bits(b.i)), 0};
            break;
          case Op::Mul:
            a = real ? Value{true, 0, x * y} : Value{false, wrap(bits(a.i) * bits(b.i)), 0};
            break;
          case Op::Div:
            a = real ? Value{true, 0, y == 0 ? 0.0 : x / y} : Value{false, int_div(a.i, b.i), 0};
            break;
          case Op::Mod:
            a = real ? Value{true, 0, y == 0 ? 0.0 : std::fmod(x, y)}
                     : Value{false, int_mod(a.i, b.i), 0};
            break;
          case Op::Eq:
            a = {false, compare(a, b) == Order::Equal, 0};
            break;
          case Op::Ne:
            a = {false, compare(a, b) != Order::Equal, 0};
            break;
          case Op::Lt:
            a = {false, compare(a, b) == Order::Less, 0};
            break;
          case Op::Le: {
            const Order o = compare(a, b);
            a = {false, o == Order::Less || o == Order::Equal, 0};
            break;
          }
          case Op::Gt:
            a = {false, compare(a, b) == Order::Greater, 0};
            break;
          case Op::Ge: {
            const Order o = compare(a, b);
            a = {false, o == Order::Greater || o == Order::Equal, 0};
            break;
          }
          case Op::And:
            a = {false, a.truthy() && b.truthy(), 0};
            break;
          case Op::Or:
            a = {false, a.truthy() || b.truthy(), 0};
            break;
          case Op::Xor:
            a = {false, a.truthy() != b.truthy(), 0};
            break;
          default:
            break;
        }
      }
    }
  }
  return sp > 0 ? st[0] : Value{};
}

}  // namespace plc::debug
