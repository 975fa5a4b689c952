#include "plc/profibus/gsd/gsd.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "plc/profibus/dp/cfg.hpp"

namespace plc::profibus::gsd {

namespace {

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// One logical line: comments removed, continuations joined.
struct Line {
  std::string text;
  std::size_t number = 0;  // of its first physical line
};

std::vector<Line> logical_lines(std::string_view text, const std::string& file) {
  std::vector<Line> out;
  Line cur;
  bool continuing = false;
  std::size_t n = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t nl = text.find('\n', pos);
    std::string_view raw =
        text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
    ++n;
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    // Cut the comment (a ';' outside a string).
    bool in_string = false;
    std::size_t cut = raw.size();
    for (std::size_t i = 0; i < raw.size(); ++i) {
      if (raw[i] == '"') in_string = !in_string;
      if (raw[i] == ';' && !in_string) {
        cut = i;
        break;
      }
    }
    if (in_string && cut == raw.size())
      throw GsdError(file, n, "a string without its closing '\"'");
    std::string_view body = trim(raw.substr(0, cut));
    const bool more = !body.empty() && body.back() == '\\';
    if (more) body = trim(body.substr(0, body.size() - 1));
    if (!continuing) {
      cur = Line{};
      cur.number = n;
    } else if (!body.empty()) {
      cur.text += ' ';
    }
    cur.text += body;
    continuing = more;
    if (!continuing && !trim(cur.text).empty()) out.push_back(cur);
  }
  if (continuing) throw GsdError(file, cur.number, "a continuation '\\' at the end of the file");
  return out;
}

bool parse_int(std::string_view s, std::int64_t& v) {
  s = trim(s);
  if (s.empty()) return false;
  bool neg = false;
  if (s.front() == '-') {
    neg = true;
    s.remove_prefix(1);
  }
  int base = 10;
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    base = 16;
    s.remove_prefix(2);
  }
  if (s.empty() || s.size() > 15) return false;  // no overflow of 64 bits
  std::int64_t r = 0;
  for (const char c : s) {
    int d;
    if (c >= '0' && c <= '9') {
      d = c - '0';
    } else if (base == 16 && std::isxdigit(static_cast<unsigned char>(c))) {
      d = std::tolower(static_cast<unsigned char>(c)) - 'a' + 10;
    } else {
      return false;
    }
    r = r * base + d;
  }
  v = neg ? -r : r;
  return true;
}

// "0x01,0x02, 3" -> bytes.
std::vector<std::uint8_t> byte_list(std::string_view s, const std::string& file, std::size_t line,
                                    const char* what) {
  std::vector<std::uint8_t> out;
  std::size_t pos = 0;
  while (pos <= s.size()) {
    const std::size_t comma = s.find(',', pos);
    const std::string_view item =
        s.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos);
    std::int64_t v = 0;
    if (!parse_int(item, v) || v < 0 || v > 255)
      throw GsdError(
          file, line,
          std::string(what) + ": '" + std::string(trim(item)) + "' is not a byte (0..255)");
    out.push_back(static_cast<std::uint8_t>(v));
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return out;
}

// `"text" rest` -> text, rest.
bool quoted(std::string_view s, std::string& text, std::string_view& rest) {
  s = trim(s);
  if (s.empty() || s.front() != '"') return false;
  const std::size_t end = s.find('"', 1);
  if (end == std::string_view::npos) return false;
  text = std::string(s.substr(1, end - 1));
  rest = trim(s.substr(end + 1));
  return true;
}

// "Key(3)" -> key "key", index 3.
bool indexed(std::string_view key, std::string& name, std::int64_t& index) {
  const std::size_t open = key.find('(');
  if (open == std::string_view::npos || key.back() != ')') return false;
  name = lower(trim(key.substr(0, open)));
  return parse_int(key.substr(open + 1, key.size() - open - 2), index);
}

void parse_prm_type(std::string_view s, ExtUserPrm& p, const std::string& file, std::size_t line) {
  // TYPE[(bits)] default min-max | TYPE default a,b,c
  std::istringstream in{std::string(s)};
  std::string type, def, range;
  in >> type >> def;
  std::getline(in, range);
  const std::size_t open = type.find('(');
  if (open != std::string::npos) {
    const std::string bits = type.substr(open + 1, type.size() - open - 2);
    type = type.substr(0, open);
    const std::size_t dash = bits.find('-');
    std::int64_t a = 0, b = 0;
    if (!parse_int(bits.substr(0, dash), a) ||
        (dash != std::string::npos && !parse_int(bits.substr(dash + 1), b)) || a < 0 || a > 7)
      throw GsdError(file, line, "bad bit position in '" + std::string(trim(s)) + "'");
    p.bit_first = static_cast<int>(a);
    p.bit_last = static_cast<int>(dash == std::string::npos ? a : b);
    if (p.bit_last < p.bit_first || p.bit_last > 7)
      throw GsdError(file, line, "bad bit area in '" + std::string(trim(s)) + "'");
  }
  static const char* const kTypes[] = {"unsigned8", "unsigned16", "unsigned32", "signed8",
                                       "signed16",  "signed32",   "bit",        "bitarea"};
  const std::string t = lower(type);
  if (std::find_if(std::begin(kTypes), std::end(kTypes), [&](const char* k) { return t == k; }) ==
      std::end(kTypes))
    throw GsdError(file, line, "unknown parameter type '" + type + "'");
  if ((t == "bit" || t == "bitarea") != (p.bit_first >= 0))
    throw GsdError(file, line, "'" + type + "' needs its bit position(s) in parentheses");
  p.type = t;
  if (!parse_int(def, p.def))
    throw GsdError(file, line, "parameter default '" + def + "' is no number");
  const std::string_view r = trim(range);
  const std::size_t dash = r.find('-', 1);
  if (!r.empty() && r.find(',') == std::string_view::npos && dash != std::string_view::npos) {
    if (!parse_int(r.substr(0, dash), p.min) || !parse_int(r.substr(dash + 1), p.max))
      throw GsdError(file, line, "bad range '" + std::string(r) + "'");
  } else if (!r.empty()) {
    std::size_t pos = 0;
    while (pos <= r.size()) {
      const std::size_t comma = r.find(',', pos);
      std::int64_t v = 0;
      if (!parse_int(r.substr(pos, comma == std::string_view::npos ? r.npos : comma - pos), v))
        throw GsdError(file, line, "bad value list '" + std::string(r) + "'");
      p.allowed.push_back(v);
      if (comma == std::string_view::npos) break;
      pos = comma + 1;
    }
    p.min = *std::min_element(p.allowed.begin(), p.allowed.end());
    p.max = *std::max_element(p.allowed.begin(), p.allowed.end());
  } else {
    throw GsdError(file, line, "parameter without its range (min-max or a list)");
  }
  if (p.def < p.min || p.def > p.max)
    throw GsdError(file, line, "default " + std::to_string(p.def) + " outside its range");
}

// Writes a parameter's default at `offset` of `data` (bits within a byte;
// Unsigned16/32 MSB first).
void apply_ref(const ExtUserPrm& p, std::size_t offset, std::vector<std::uint8_t>& data) {
  std::size_t width = 1;
  if (p.type == "unsigned16" || p.type == "signed16") width = 2;
  if (p.type == "unsigned32" || p.type == "signed32") width = 4;
  if (data.size() < offset + width) data.resize(offset + width, 0);
  if (p.bit_first >= 0) {
    const int n = p.bit_last - p.bit_first + 1;
    const std::uint8_t mask = static_cast<std::uint8_t>(((1u << n) - 1u) << p.bit_first);
    data[offset] = static_cast<std::uint8_t>(
        (data[offset] & ~mask) | ((static_cast<unsigned>(p.def) << p.bit_first) & mask));
    return;
  }
  const auto v = static_cast<std::uint64_t>(p.def);
  for (std::size_t i = 0; i < width; ++i)
    data[offset + i] = static_cast<std::uint8_t>(v >> (8 * (width - 1 - i)));
}

}  // namespace

const Value* Gsd::find(std::string_view key) const {
  const auto it = keys.find(lower(key));
  return it == keys.end() ? nullptr : &it->second;
}

std::string Gsd::text(std::string_view key, const std::string& def) const {
  const Value* v = find(key);
  return v ? v->text : def;
}

std::int64_t Gsd::number(std::string_view key, std::int64_t def) const {
  const Value* v = find(key);
  if (!v) return def;
  std::int64_t n = 0;
  if (!parse_int(v->text, n))
    throw GsdError(file, v->line, std::string(key) + ": '" + v->text + "' is not a number");
  return n;
}

std::size_t Gsd::max_modules() const { return static_cast<std::size_t>(number("Max_Module", 1)); }

bool Gsd::baud_supported(const char* suffix) const {
  return number(std::string(suffix) + "_supp", 0) != 0;
}

std::optional<std::uint32_t> Gsd::max_tsdr(const char* suffix) const {
  if (!find(std::string("MaxTsdr_") + suffix)) return std::nullopt;
  return static_cast<std::uint32_t>(number(std::string("MaxTsdr_") + suffix, 0));
}

std::uint32_t Gsd::min_slave_interval() const {
  return static_cast<std::uint32_t>(number("Min_Slave_Intervall", 1));
}

const Module* Gsd::module(std::string_view name) const {
  for (const Module& m : modules)
    if (m.name == name) return &m;
  const std::string l = lower(name);
  for (const Module& m : modules)
    if (lower(m.name) == l) return &m;
  return nullptr;
}

std::vector<std::uint8_t> Gsd::user_prm_data(const std::vector<const Module*>& chosen) const {
  std::vector<std::uint8_t> data;
  if (const Value* v = find("User_Prm_Data"))
    data = byte_list(v->text, file, v->line, "User_Prm_Data");
  const auto len = static_cast<std::size_t>(number("User_Prm_Data_Len", 0));
  if (data.size() < len) data.resize(len, 0);
  auto apply = [&](const std::vector<PrmConst>& cs, const std::vector<PrmRef>& rs,
                   std::size_t base) {
    for (const PrmConst& c : cs) {
      if (data.size() < base + c.offset + c.bytes.size())
        data.resize(base + c.offset + c.bytes.size(), 0);
      std::copy(c.bytes.begin(), c.bytes.end(),
                data.begin() + static_cast<std::ptrdiff_t>(base + c.offset));
    }
    for (const PrmRef& r : rs) {
      const auto it = ext_user_prm.find(r.reference);
      if (it != ext_user_prm.end()) apply_ref(it->second, base + r.offset, data);
    }
  };
  apply(consts, refs, 0);
  for (const Module* m : chosen) {
    const std::size_t base = data.size();
    data.resize(base + m->prm_len, 0);
    apply(m->consts, m->refs, base);
  }
  return data;
}

Gsd parse_gsd(std::string_view text, const std::string& file) {
  Gsd g;
  g.file = file;
  const std::vector<Line> lines = logical_lines(text, file);
  bool header = false;
  enum class Block { None, Module, ExtPrm, PrmText } block = Block::None;
  Module mod;
  ExtUserPrm prm;
  PrmText ptext;
  for (const Line& ln : lines) {
    const std::string_view s = trim(ln.text);
    const std::size_t eq = s.find('=');
    const std::string key = lower(trim(s.substr(0, eq)));
    const std::string_view value = eq == std::string_view::npos ? "" : trim(s.substr(eq + 1));
    auto fail = [&](const std::string& m) { throw GsdError(file, ln.number, m); };
    if (key == "#profibus_dp") {
      header = true;
      continue;
    }
    if (!header) fail("'" + std::string(s) + "' before #Profibus_DP");
    if (eq == std::string_view::npos) {
      if (key == "endmodule") {
        if (block != Block::Module) fail("EndModule without Module");
        g.modules.push_back(mod);
        block = Block::None;
      } else if (key == "endextuserprmdata") {
        if (block != Block::ExtPrm) fail("EndExtUserPrmData without ExtUserPrmData");
        g.ext_user_prm[prm.reference] = prm;
        block = Block::None;
      } else if (key == "endprmtext") {
        if (block != Block::PrmText) fail("EndPrmText without PrmText");
        g.prm_texts[ptext.reference] = ptext;
        block = Block::None;
      } else if (block == Block::Module && mod.cfg.size() > 0 && !mod.reference) {
        std::int64_t r = 0;
        if (!parse_int(s, r) || r < 0) fail("'" + std::string(s) + "': not a module reference");
        mod.reference = static_cast<std::uint32_t>(r);
      } else if (block == Block::ExtPrm && prm.type.empty()) {
        parse_prm_type(s, prm, file, ln.number);
      } else {
        fail("'" + std::string(s) +
             "' is not 'Keyword = Value' (a comment wrapped onto a line of its own?)");
      }
      continue;
    }
    if (key.empty()) fail("'=' without a keyword");
    if (key == "module") {
      if (block != Block::None) fail("Module inside another block");
      mod = Module{};
      mod.line = ln.number;
      std::string_view rest;
      if (!quoted(value, mod.name, rest)) fail("Module = \"name\" CFG bytes: the name is missing");
      if (rest.empty()) fail("module '" + mod.name + "' without Cfg bytes");
      mod.cfg = byte_list(rest, file, ln.number, "Cfg byte");
      const auto sz = dp::cfg_sizes(mod.cfg);
      if (!sz) fail("module '" + mod.name + "': malformed Cfg bytes " + dp::hex(mod.cfg));
      mod.input_bytes = sz->input_bytes;
      mod.output_bytes = sz->output_bytes;
      block = Block::Module;
      continue;
    }
    if (key == "extuserprmdata") {
      if (block != Block::None) fail("ExtUserPrmData inside another block");
      prm = ExtUserPrm{};
      prm.line = ln.number;
      const std::size_t sp = value.find_first_of(" \t\"");
      std::int64_t r = 0;
      std::string_view rest;
      if (!parse_int(value.substr(0, sp), r) || r < 0 ||
          !quoted(value.substr(sp == std::string_view::npos ? value.size() : sp), prm.name, rest))
        fail("ExtUserPrmData = REFERENCE \"name\"");
      prm.reference = static_cast<std::uint32_t>(r);
      block = Block::ExtPrm;
      continue;
    }
    if (key == "prmtext") {
      if (block != Block::None) fail("PrmText inside another block");
      ptext = PrmText{};
      std::int64_t r = 0;
      if (!parse_int(value, r) || r < 0) fail("PrmText = REFERENCE");
      ptext.reference = static_cast<std::uint32_t>(r);
      block = Block::PrmText;
      continue;
    }
    std::string name;
    std::int64_t index = 0;
    const bool has_index = indexed(trim(s.substr(0, eq)), name, index);
    if (block == Block::PrmText) {
      std::string t;
      std::string_view rest;
      if (!has_index || name != "text" || !quoted(value, t, rest)) fail("Text(VALUE) = \"text\"");
      ptext.texts[index] = t;
      continue;
    }
    if (block == Block::ExtPrm) {
      if (key != "prm_text_ref") fail("'" + key + "' inside ExtUserPrmData");
      std::int64_t r = 0;
      if (!parse_int(value, r) || r < 0) fail("Prm_Text_Ref = REFERENCE");
      prm.text_ref = static_cast<std::uint32_t>(r);
      continue;
    }
    if (has_index && (name == "ext_user_prm_data_const" || name == "ext_user_prm_data_ref")) {
      if (index < 0 || index > 237)
        fail("parameter offset " + std::to_string(index) + " outside 0..237");
      auto& consts = block == Block::Module ? mod.consts : g.consts;
      auto& refs = block == Block::Module ? mod.refs : g.refs;
      if (name == "ext_user_prm_data_const") {
        consts.push_back({static_cast<std::size_t>(index),
                          byte_list(value, file, ln.number, "Ext_User_Prm_Data_Const")});
      } else {
        std::int64_t r = 0;
        if (!parse_int(value, r) || r < 0) fail("Ext_User_Prm_Data_Ref = REFERENCE");
        refs.push_back({static_cast<std::size_t>(index), static_cast<std::uint32_t>(r)});
      }
      continue;
    }
    if (block == Block::Module) {
      if (key == "ext_module_prm_data_len") {
        std::int64_t n = 0;
        if (!parse_int(value, n) || n < 0 || n > 237) fail("Ext_Module_Prm_Data_Len: 0..237");
        mod.prm_len = static_cast<std::size_t>(n);
      }
      continue;  // other module keywords (Data_Area, Info_Text, ...) are not used
    }
    std::string v(value);
    std::string_view rest;
    std::string unq;
    if (quoted(value, unq, rest) && rest.empty()) v = unq;
    g.keys[key] = Value{v, ln.number};
  }
  if (!header) throw GsdError(file, lines.empty() ? 1 : lines.back().number, "no #Profibus_DP");
  if (block != Block::None)
    throw GsdError(file, lines.back().number, "the file ends inside a block");
  if (!g.find("Ident_Number")) throw GsdError(file, 1, "Ident_Number missing");
  const std::int64_t id = g.number("Ident_Number", 0);
  if (id < 0 || id > 0xFFFF)
    throw GsdError(file, g.find("Ident_Number")->line, "Ident_Number outside 0..0xFFFF");
  for (const PrmRef& r : g.refs)
    if (!g.ext_user_prm.count(r.reference))
      throw GsdError(file, 1,
                     "Ext_User_Prm_Data_Ref to undefined parameter " + std::to_string(r.reference));
  for (const Module& m : g.modules)
    for (const PrmRef& r : m.refs)
      if (!g.ext_user_prm.count(r.reference))
        throw GsdError(file, m.line,
                       "module '" + m.name + "': Ext_User_Prm_Data_Ref to undefined parameter " +
                           std::to_string(r.reference));
  return g;
}

Gsd load_gsd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw GsdError(path, 0, "cannot read the file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_gsd(ss.str(), path);
}

}  // namespace plc::profibus::gsd
