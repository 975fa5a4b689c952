#include "plc/debug/condition.hpp"

#include <array>
#include <cctype>
#include <cmath>

#include "plc/iec_literal.hpp"

namespace plc::debug {

Value read_value(const VarInfo& v) {
  alignas(8) unsigned char buf[16] = {};
  Value out;
  if (v.type == VarType::STRING) return out;  // strings compare as 0
  VarRegistry::read(v, buf);
  switch (v.type) {
    case VarType::BOOL:
      out.i = *reinterpret_cast<bool*>(buf) ? 1 : 0;
      break;
    case VarType::SINT:
      out.i = *reinterpret_cast<std::int8_t*>(buf);
      break;
    case VarType::INT:
      out.i = *reinterpret_cast<std::int16_t*>(buf);
      break;
    case VarType::DINT:
      out.i = *reinterpret_cast<std::int32_t*>(buf);
      break;
    case VarType::LINT:
    case VarType::TIME:
      out.i = *reinterpret_cast<std::int64_t*>(buf);
      break;
    case VarType::USINT:
    case VarType::BYTE:
      out.i = *reinterpret_cast<std::uint8_t*>(buf);
      break;
    case VarType::UINT:
    case VarType::WORD:
      out.i = *reinterpret_cast<std::uint16_t*>(buf);
      break;
    case VarType::UDINT:
    case VarType::DWORD:
      out.i = *reinterpret_cast<std::uint32_t*>(buf);
      break;
    case VarType::ULINT:
    case VarType::LWORD:
      out.i = static_cast<std::int64_t>(*reinterpret_cast<std::uint64_t*>(buf));
      break;
    case VarType::REAL:
      out.real = true;
      out.d = *reinterpret_cast<float*>(buf);
      break;
    case VarType::LREAL:
      out.real = true;
      out.d = *reinterpret_cast<double*>(buf);
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
  if (max_depth > 32) {
    error = "condition too deeply nested (more than 32 operands pending)";
    return std::nullopt;
  }
  return c;
}

Value Condition::evaluate() const {
  std::array<Value, 32> st;
  int sp = 0;
  auto bin_cmp = [](const Value& a, const Value& b) -> int {
    if (a.real || b.real) return a.as_real() < b.as_real() ? -1 : a.as_real() > b.as_real() ? 1 : 0;
    return a.i < b.i ? -1 : a.i > b.i ? 1 : 0;
  };
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
          a.i = -a.i;
        break;
      }
      case Op::Not:
        st[sp - 1] = {false, st[sp - 1].truthy() ? 0 : 1, 0};
        break;
      default: {
        const Value b = st[--sp];
        Value& a = st[sp - 1];
        const bool real = a.real || b.real;
        switch (in.op) {
          case Op::Add:
            if (real)
              a = {true, 0, a.as_real() + b.as_real()};
            else
              a.i += b.i;
            break;
          case Op::Sub:
            if (real)
              a = {true, 0, a.as_real() - b.as_real()};
            else
              a.i -= b.i;
            break;
          case Op::Mul:
            if (real)
              a = {true, 0, a.as_real() * b.as_real()};
            else
              a.i *= b.i;
            break;
          case Op::Div:
            if (real)
              a = {true, 0, b.as_real() == 0 ? 0.0 : a.as_real() / b.as_real()};
            else
              a.i = b.i == 0 ? 0 : a.i / b.i;  // division by zero gives 0, never a trap
            break;
          case Op::Mod:
            if (real)
              a = {true, 0, b.as_real() == 0 ? 0.0 : std::fmod(a.as_real(), b.as_real())};
            else
              a.i = b.i == 0 ? 0 : a.i % b.i;
            break;
          case Op::Eq:
            a = {false, bin_cmp(a, b) == 0, 0};
            break;
          case Op::Ne:
            a = {false, bin_cmp(a, b) != 0, 0};
            break;
          case Op::Lt:
            a = {false, bin_cmp(a, b) < 0, 0};
            break;
          case Op::Le:
            a = {false, bin_cmp(a, b) <= 0, 0};
            break;
          case Op::Gt:
            a = {false, bin_cmp(a, b) > 0, 0};
            break;
          case Op::Ge:
            a = {false, bin_cmp(a, b) >= 0, 0};
            break;
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
