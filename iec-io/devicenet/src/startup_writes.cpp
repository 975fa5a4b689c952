#include "plc/devicenet/startup_writes.hpp"

#include <charconv>

#include "plc/io/model_params.hpp"

namespace plc::devicenet {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

bool number(const std::string& s, unsigned max, std::uint8_t& out) {
  unsigned v = 0;
  const bool hex = s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
  const char* b = s.data() + (hex ? 2 : 0);
  const char* e = s.data() + s.size();
  auto [p, ec] = std::from_chars(b, e, v, hex ? 16 : 10);
  if (ec != std::errc() || p != e || b == e || v > max) return false;
  out = static_cast<std::uint8_t>(v);
  return true;
}

}  // namespace

std::vector<AttributeWrite> parse_startup_writes(const std::string& text) {
  std::vector<AttributeWrite> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const auto semi = text.find(';', pos);
    const std::string item =
        trim(text.substr(pos, semi == std::string::npos ? std::string::npos : semi - pos));
    pos = semi == std::string::npos ? text.size() + 1 : semi + 1;
    if (item.empty()) continue;
    auto bad = [&](const std::string& why) {
      throw io::ParamError("startup", "start-up write '" + item + "': " + why +
                                          " (expected CLASS/INSTANCE/ATTRIBUTE=HEXBYTES, e.g. "
                                          "0x2A/1/22=03)");
    };
    const auto eq = item.find('=');
    if (eq == std::string::npos) bad("no '='");
    const std::string path = trim(item.substr(0, eq));
    const std::string hex = trim(item.substr(eq + 1));
    const auto s1 = path.find('/');
    const auto s2 = s1 == std::string::npos ? s1 : path.find('/', s1 + 1);
    if (s2 == std::string::npos) bad("the path needs class/instance/attribute");
    AttributeWrite w;
    if (!number(trim(path.substr(0, s1)), 255, w.cls) ||
        !number(trim(path.substr(s1 + 1, s2 - s1 - 1)), 255, w.instance) ||
        !number(trim(path.substr(s2 + 1)), 255, w.attribute))
      bad("class, instance and attribute are numbers 0..255");
    std::string digits;
    for (char c : hex)
      if (c != ' ') digits += c;
    if (digits.empty() || digits.size() % 2 != 0 || digits.size() / 2 > 200)
      bad("data must be 1..200 bytes as pairs of hex digits");
    for (std::size_t i = 0; i < digits.size(); i += 2) {
      std::uint8_t b = 0;
      if (!number("0x" + digits.substr(i, 2), 255, b))
        bad("'" + digits.substr(i, 2) + "' is not hex");
      w.data.push_back(b);
    }
    out.push_back(std::move(w));
  }
  return out;
}

}  // namespace plc::devicenet
