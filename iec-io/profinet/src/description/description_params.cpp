#include "plc/profinet/description/description_params.hpp"

#include <algorithm>
#include <boost/algorithm/string/trim.hpp>
#include <map>
#include <sstream>

#include "plc/iec_literal.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/description/gsdml.hpp"

namespace plc::profinet {

namespace {

// The keys of the description (every model); "submodule." and "records."
// keys are matched by prefix.
const char* const kKeys[] = {"station_name", "ip",        "netmask",       "gateway",
                             "vendor_id",    "device_id", "instance",      "min_device_interval",
                             "gsdml",        "gsdml_dap", "gsdml_modules", "dap"};

bool is_description_key(const std::string& k) {
  if (k.rfind("submodule.", 0) == 0 || k.rfind("records.", 0) == 0) return true;
  return std::find(std::begin(kKeys), std::end(kKeys), k) != std::end(kKeys);
}

std::uint64_t number(const std::string& key, const std::string& text, std::uint64_t max,
                     const std::string& what) {
  const auto v = parse_iec_unsigned(text);
  if (!v || *v > max)
    throw io::ParamError(key, what + " '" + text + "' is not a number 0.." + std::to_string(max));
  return *v;
}

// "S.SS" after a "submodule." / "records." prefix.
std::pair<std::uint16_t, std::uint16_t> slot_subslot(const std::string& key, std::size_t prefix) {
  const std::string rest = key.substr(prefix);
  const auto dot = rest.find('.');
  if (dot == std::string::npos)
    throw io::ParamError(key, "'" + key + "': expected " + key.substr(0, prefix) +
                                  "SLOT.SUBSLOT, e.g. " + key.substr(0, prefix) + "1.1");
  return {static_cast<std::uint16_t>(number(key, rest.substr(0, dot), 0x7FFF, "slot")),
          static_cast<std::uint16_t>(number(key, rest.substr(dot + 1), 0xFFFF, "subslot"))};
}

// "a=1 b=0x2" -> {a: "1", b: "0x2"}; every name must be in `allowed`.
std::map<std::string, std::string> fields(const std::string& key, const std::string& text,
                                          std::initializer_list<const char*> allowed) {
  std::map<std::string, std::string> out;
  std::istringstream in(text);
  std::string item;
  while (in >> item) {
    const auto eq = item.find('=');
    const std::string name = item.substr(0, eq);
    if (eq == std::string::npos || eq + 1 == item.size())
      throw io::ParamError(key, "'" + item + "': expected NAME=VALUE");
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return name == a; })) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      throw io::ParamError(key, "unknown field '" + name + "' (fields: " + list + ")");
    }
    if (out.count(name)) throw io::ParamError(key, "field '" + name + "' given twice");
    out[name] = item.substr(eq + 1);
  }
  return out;
}

std::string trim(const std::string& s) { return boost::algorithm::trim_copy(s); }

// "INDEX=HEXBYTES; INDEX=HEXBYTES" (spaces between bytes allowed).
std::vector<StartupRecord> parse_records(const std::string& key, const std::string& text) {
  std::vector<StartupRecord> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const auto semi = text.find(';', pos);
    const std::string item =
        trim(text.substr(pos, semi == std::string::npos ? std::string::npos : semi - pos));
    pos = semi == std::string::npos ? text.size() + 1 : semi + 1;
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw io::ParamError(
          key, "start-up record '" + item + "': expected INDEX=HEXBYTES, e.g. 0xB02E=0102A0");
    StartupRecord r;
    r.index = static_cast<std::uint16_t>(number(key, trim(item.substr(0, eq)), 0xFFFF, "index"));
    std::string digits;
    for (char c : item.substr(eq + 1))
      if (c != ' ') digits += c;
    if (digits.empty() || digits.size() % 2 != 0 || digits.size() / 2 > 4096)
      throw io::ParamError(
          key, "start-up record '" + item + "': data must be 1..4096 bytes as pairs of hex digits");
    for (std::size_t i = 0; i < digits.size(); i += 2) {
      const auto b = parse_iec_unsigned("16#" + digits.substr(i, 2));
      if (!b || digits[i] == '_' || digits[i + 1] == '_')
        throw io::ParamError(
            key, "start-up record '" + item + "': '" + digits.substr(i, 2) + "' is not hex");
      r.data.push_back(static_cast<std::uint8_t>(*b));
    }
    out.push_back(std::move(r));
  }
  return out;
}

SubmoduleDescription* find_submodule(DeviceDescription& d, std::uint16_t slot,
                                     std::uint16_t subslot) {
  for (auto& m : d.modules)
    if (m.slot == slot)
      for (auto& s : m.submodules)
        if (s.subslot == subslot) return &s;
  return nullptr;
}

DeviceDescription generic(const io::ModelParams& p) {
  DeviceDescription d;
  const auto dap =
      fields("dap", p.get_string("dap", ""), {"module", "submodule", "interface", "port"});
  if (!dap.count("module"))
    throw io::ParamError("dap",
                         "a generic device needs dap: \"module=IDENT ...\" (the DAP's "
                         "module ident number)");
  auto ident = [&](const std::map<std::string, std::string>& f, const char* name, std::uint32_t def,
                   const std::string& key) -> std::uint32_t {
    auto it = f.find(name);
    return it == f.end() ? def
                         : static_cast<std::uint32_t>(number(key, it->second, 0xFFFFFFFF, name));
  };
  ModuleDescription m0;
  m0.slot = 0;
  m0.module_ident = ident(dap, "module", 0, "dap");
  m0.submodules = {{kDapSubslot, 0, ident(dap, "submodule", 1, "dap"), 0, 0, {}},
                   {kInterfaceSubslot, 0, ident(dap, "interface", 0x8000, "dap"), 0, 0, {}},
                   {kPortSubslot, 0, ident(dap, "port", 0x8001, "dap"), 0, 0, {}}};
  d.modules.push_back(std::move(m0));
  std::map<std::uint16_t, ModuleDescription> slots;
  for (const auto& [key, value] : p.values()) {
    if (key.rfind("submodule.", 0) != 0) continue;
    const auto [slot, subslot] = slot_subslot(key, 10);
    if (slot == 0) throw io::ParamError(key, "slot 0 is the DAP: describe it with dap:");
    const auto f = fields(key, p.get_string(key, ""), {"module", "submodule", "api", "in", "out"});
    if (!f.count("module") || !f.count("submodule"))
      throw io::ParamError(key, "a submodule needs module=IDENT and submodule=IDENT");
    auto& m = slots[slot];
    const std::uint32_t mod = ident(f, "module", 0, key);
    if (!m.submodules.empty() && m.module_ident != mod)
      throw io::ParamError(key, "slot " + std::to_string(slot) + " has two module idents");
    m.slot = slot;
    m.module_ident = mod;
    SubmoduleDescription s;
    s.subslot = subslot;
    s.submodule_ident = ident(f, "submodule", 0, key);
    s.api = ident(f, "api", 0, key);
    // IO data of one submodule fit one 1440-byte RT_CLASS_1 frame.
    if (f.count("in"))
      s.input_length = static_cast<std::uint16_t>(number(key, f.at("in"), 1439, "in"));
    if (f.count("out"))
      s.output_length = static_cast<std::uint16_t>(number(key, f.at("out"), 1439, "out"));
    m.submodules.push_back(std::move(s));
  }
  for (auto& [slot, m] : slots) {
    std::sort(m.submodules.begin(), m.submodules.end(),
              [](const auto& a, const auto& b) { return a.subslot < b.subslot; });
    d.modules.push_back(std::move(m));
  }
  return d;
}

DeviceDescription from_gsdml(const io::ModelParams& p) {
  // A relative file is taken from the config file's folder.
  const std::string path = p.get_path("gsdml");
  if (path.empty()) throw io::ParamError("gsdml", "model gsdml needs gsdml: FILE");
  GsdmlSelection sel;
  sel.dap = p.get_string("gsdml_dap", "");
  try {
    sel.modules = parse_gsdml_modules(p.get_string("gsdml_modules", ""));
  } catch (const std::invalid_argument& e) {
    throw io::ParamError("gsdml_modules", e.what());
  }
  try {
    return load_gsdml(path, sel);
  } catch (const GsdmlError& e) {
    throw io::ParamError("gsdml", e.what());
  }
}

}  // namespace

DeviceDescription description_from_params(const std::string& model, const io::ModelParams& p) {
  // Keys of another model's form are a config mistake, not to be ignored.
  for (const auto& [key, value] : p.values()) {
    const bool gsdml_key = key.rfind("gsdml", 0) == 0;
    const bool generic_key = key == "dap" || key.rfind("submodule.", 0) == 0;
    if ((gsdml_key && model != "gsdml") || (generic_key && model != "generic"))
      throw io::ParamError(key, "key '" + key + "' belongs to model " +
                                    (gsdml_key ? "gsdml" : "generic") + ", not '" + model + "'");
  }
  DeviceDescription d = model == "gsdml"     ? from_gsdml(p)
                        : model == "generic" ? generic(p)
                                             : builtin_description(model, p);

  d.station_name = p.get_string("station_name", "");
  if (!p.has("station_name"))
    throw io::ParamError("station_name", "every PROFINET device needs its station_name");
  if (auto why = station_name_problem(d.station_name); !why.empty())
    throw io::ParamError("station_name", why);
  auto ip = [&](const char* key, Ipv4 def) {
    const std::string s = p.get_string(key, "");
    if (!p.has(key)) return def;
    const auto v = parse_ipv4(s);
    if (!v) throw io::ParamError(key, "'" + s + "' is not an IPv4 address a.b.c.d");
    return *v;
  };
  if (!p.has("ip")) throw io::ParamError("ip", "every PROFINET device needs its ip");
  d.ip = ip("ip", {});
  d.netmask = ip("netmask", d.netmask);
  d.gateway = ip("gateway", d.gateway);
  d.vendor_id = static_cast<std::uint16_t>(p.get_int("vendor_id", d.vendor_id, 0, 0xFFFF));
  d.device_id = static_cast<std::uint16_t>(p.get_int("device_id", d.device_id, 0, 0xFFFF));
  d.instance = static_cast<std::uint16_t>(p.get_int("instance", d.instance, 0, 0xFFFF));
  // The controller's cycles span 250 us .. 4 ms x reduction ratio (issue 11).
  d.min_device_interval = p.get_time("min_device_interval", d.min_device_interval,
                                     std::chrono::microseconds(250), std::chrono::seconds(1));
  for (const auto& [key, value] : p.values()) {
    if (key.rfind("records.", 0) != 0) continue;
    const auto [slot, subslot] = slot_subslot(key, 8);
    SubmoduleDescription* s = find_submodule(d, slot, subslot);
    if (!s)
      throw io::ParamError(key, "the description has no submodule in slot " + std::to_string(slot) +
                                    " subslot " + std::to_string(subslot));
    auto recs = parse_records(key, p.get_string(key, ""));
    s->records.insert(s->records.end(), recs.begin(), recs.end());
  }
  if (auto why = check(d); !why.empty()) throw io::ParamError("", why);
  return d;
}

io::ModelParams model_params_of(const io::ModelParams& params) {
  io::ModelParams out;
  out.set_folder(params.folder());
  for (const auto& [k, v] : params.values())
    if (!is_description_key(k)) out.set(k, v);
  return out;
}

}  // namespace plc::profinet
