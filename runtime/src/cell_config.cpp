// YAML cell-config loader. Every error names file:line:column and the key.
#include "plc/cell_config.hpp"

#include <arpa/inet.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>

#include "plc/config_path.hpp"
#include "plc/iec_literal.hpp"

namespace plc {

namespace {

// "file:line:column: message"; "file: message" where no line is known (the
// file cannot be read), the message alone without a file.
std::string located(const std::string& file, Mark m, const std::string& msg) {
  if (file.empty()) return msg;
  if (m.line == 0) return file + ": " + msg;
  return file + ":" + std::to_string(m.line) + ":" + std::to_string(m.column) + ": " + msg;
}

}  // namespace

ConfigError::ConfigError(const std::string& f, Mark m, const std::string& msg)
    : std::runtime_error(located(f, m, msg)), file(f), mark(m), message(msg) {}

namespace {

Mark mark_of(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  if (m.line < 0) return {};
  return {m.line + 1, m.column + 1};
}

class Loader {
 public:
  explicit Loader(std::string file) : file_(std::move(file)), folder_(config_folder(file_)) {}

  [[noreturn]] void fail(Mark m, const std::string& msg) const { throw ConfigError(file_, m, msg); }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& msg) const {
    fail(mark_of(n), msg);
  }

  void expect_map(const YAML::Node& n, const std::string& what) const {
    if (!n.IsMap()) fail(n, what + " must be a mapping (key: value)");
  }

  // Rejects keys not in `allowed`, naming the key and the allowed ones.
  void check_keys(const YAML::Node& n, const std::set<std::string>& allowed,
                  const std::string& what) const {
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string key = it->first.Scalar();
      if (!allowed.count(key)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(it->first,
             "unknown key '" + key + "' in " + what + " (expected one of: " + list + ")");
      }
    }
  }

  const YAML::Node require(const YAML::Node& n, const std::string& key,
                           const std::string& what) const {
    const YAML::Node v = n[key];
    if (!v) fail(n, "missing key '" + key + "' in " + what);
    return v;
  }

  // A path written in this config: relative ones are taken from its folder.
  std::string in_folder(const std::string& path) const { return path_in_folder(folder_, path); }

  Item<std::string> scalar(const YAML::Node& v, const std::string& key) const {
    if (!v.IsScalar()) fail(v, "key '" + key + "' must be a single value");
    return {v.Scalar(), mark_of(v)};
  }

  Item<TIME> time(const YAML::Node& v, const std::string& key) const {
    auto s = scalar(v, key);
    auto t = parse_iec_time(s.value);
    if (!t) fail(v, "key '" + key + "': '" + s.value + "' is not a duration (e.g. 1ms, T#10ms)");
    return {*t, s.mark};
  }

  Item<std::int64_t> integer(const YAML::Node& v, const std::string& key, std::int64_t min,
                             std::int64_t max) const {
    auto s = scalar(v, key);
    auto i = parse_iec_integer(s.value);
    if (!i) fail(v, "key '" + key + "': '" + s.value + "' is not an integer");
    if (*i < min || *i > max)
      fail(v, "key '" + key + "': " + s.value + " out of range [" + std::to_string(min) + ", " +
                  std::to_string(max) + "]");
    return {*i, s.mark};
  }

  // A model's parameters. Nested mappings are flattened into dotted keys
  // (`u1: {type: INT}` gives "u1.type", with the mark of `type`); a list of
  // values, or of lists of values, arrives as its flow text ("[1, 2]",
  // "[[1, 0], [0, 1]]") for ModelParams::get_list/get_matrix.
  Params params(const YAML::Node& v, const std::string& key) const {
    Params p;
    p.mark = mark_of(v);
    p.values.set_folder(folder_);  // a file parameter (gsdml:, pcap:) is taken from there
    if (!v.IsMap()) fail(v, "key '" + key + "' must be a mapping of parameter: value");
    flatten_params(v, "", p, 0);
    return p;
  }

  void flatten_params(const YAML::Node& map, const std::string& prefix, Params& p,
                      int depth) const {
    for (auto it = map.begin(); it != map.end(); ++it) {
      // Copies: the iterator's pair is a temporary proxy.
      const YAML::Node key = it->first;
      const YAML::Node val = it->second;
      const std::string k = prefix + key.Scalar();
      if (val.IsMap()) {
        // Two levels are all a model needs (u1: {raw: [..]}); deeper is a
        // mistake in the config's indentation more often than a design.
        if (depth >= 2) fail(val, "parameter '" + k + "' nests too deep (at most two levels)");
        p.marks[k] = mark_of(key);
        flatten_params(val, k + ".", p, depth + 1);
      } else if (val.IsSequence()) {
        p.values.set(k, flow_list(val, k, 0));
        p.marks[k] = mark_of(key);
      } else if (val.IsScalar()) {
        p.values.set(k, val.Scalar());
        p.marks[k] = mark_of(key);
      } else {
        fail(val.IsNull() ? key : val, "parameter '" + k + "' has no value");
      }
    }
  }

  std::string flow_list(const YAML::Node& seq, const std::string& k, int depth) const {
    std::string out = "[";
    for (std::size_t i = 0; i < seq.size(); ++i) {
      const YAML::Node e = seq[i];
      if (i) out += ", ";
      if (e.IsScalar()) {
        out += e.Scalar();
      } else if (e.IsSequence() && depth == 0) {
        out += flow_list(e, k, 1);
      } else {
        fail(e, "parameter '" + k + "': a list holds values or lists of values (a matrix's rows)");
      }
    }
    return out + "]";
  }

  std::vector<std::pair<Item<std::string>, Item<std::string>>> string_map(
      const YAML::Node& v, const std::string& key) const {
    std::vector<std::pair<Item<std::string>, Item<std::string>>> out;
    if (!v.IsMap()) fail(v, "key '" + key + "' must be a mapping");
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (!it->second.IsScalar())
        fail(it->second, "'" + it->first.Scalar() + "' must be a single value");
      out.push_back(
          {{it->first.Scalar(), mark_of(it->first)}, {it->second.Scalar(), mark_of(it->second)}});
    }
    return out;
  }

  template <class F>
  void each(const YAML::Node& root, const std::string& key, F f) const {
    const YAML::Node list = root[key];
    if (!list) return;
    if (!list.IsSequence()) fail(list, "key '" + key + "' must be a list (items start with '- ')");
    for (const auto& item : list) f(item);
  }

  CellConfig load(const YAML::Node& root) {
    CellConfig c;
    c.file = file_;
    if (!root || root.IsNull()) fail(Mark{1, 1}, "the config is empty");
    expect_map(root, "the cell config");
    check_keys(root,
               {"cell", "clock", "image", "tasks", "programs", "plugins", "devices", "safe_values",
                "retain", "libraries", "hmi"},
               "the cell config");
    if (root["cell"]) c.cell = scalar(root["cell"], "cell");
    each(root, "libraries", [&](const YAML::Node& n) {
      auto lib = scalar(n, "libraries");
      if (lib.value.empty()) fail(n, "key 'libraries': an empty path");
      // Absolute: the path is the library's identity (a debugger `reload`
      // names it from its own current directory, a recording keeps it).
      std::string why;
      const auto abs = absolute_path(in_folder(lib.value), why);
      if (!abs) fail(n, "key 'libraries': " + lib.value + ": " + why);
      lib.value = *abs;
      c.libraries.push_back(std::move(lib));
    });
    if (const auto n = root["clock"]) {
      auto s = scalar(n, "clock");
      if (s.value == "virtual")
        c.clock = {io::ClockMode::Virtual, s.mark};
      else if (s.value == "realtime")
        c.clock = {io::ClockMode::RealTime, s.mark};
      else
        fail(n, "key 'clock': '" + s.value + "' is not virtual or realtime");
    }
    if (const auto n = root["image"]) {
      expect_map(n, "image");
      check_keys(n, {"inputs", "outputs", "memory", "byte_order"}, "image");
      c.image_mark = mark_of(n);
      constexpr std::int64_t kMax = 1 << 20;
      if (n["inputs"]) c.image.inputs = std::size_t(integer(n["inputs"], "inputs", 0, kMax).value);
      if (n["outputs"])
        c.image.outputs = std::size_t(integer(n["outputs"], "outputs", 0, kMax).value);
      if (n["memory"]) c.image.memory = std::size_t(integer(n["memory"], "memory", 0, kMax).value);
      if (const auto b = n["byte_order"]) {
        auto s = scalar(b, "byte_order");
        if (s.value == "big")
          c.byte_order = {io::ByteOrder::Big, s.mark};
        else if (s.value == "little")
          c.byte_order = {io::ByteOrder::Little, s.mark};
        else
          fail(b, "key 'byte_order': '" + s.value + "' is not big or little");
      }
    }
    each(root, "tasks", [&](const YAML::Node& n) { c.tasks.push_back(task(n)); });
    each(root, "programs", [&](const YAML::Node& n) { c.programs.push_back(program(n)); });
    each(root, "plugins", [&](const YAML::Node& n) { c.plugins.push_back(plugin(n)); });
    each(root, "devices", [&](const YAML::Node& n) { c.devices.push_back(device(n)); });
    if (const auto n = root["safe_values"]) {
      for (auto& [a, v] : string_map(n, "safe_values")) c.safe_values.push_back({a, v});
    }
    if (const auto n = root["retain"]) c.retain = retain(n, c.image);
    if (const auto n = root["hmi"]) c.hmi = hmi(n);
    if (c.tasks.empty()) fail(root, "the cell config declares no tasks (key 'tasks')");
    cross_check(c);
    return c;
  }

  TaskConfig task(const YAML::Node& n) {
    TaskConfig t;
    t.mark = mark_of(n);
    expect_map(n, "a task");
    check_keys(n, {"name", "period", "priority", "programs", "watchdog"}, "task");
    t.name = scalar(require(n, "name", "task"), "name");
    t.period = time(require(n, "period", "task '" + t.name.value + "'"), "period");
    if (t.period.value < kMinPeriod || t.period.value > kMaxPeriod)
      fail(n["period"], "key 'period': " + format_iec_time(t.period.value) + " out of range [" +
                            format_iec_time(kMinPeriod) + ", " + format_iec_time(kMaxPeriod) + "]");
    if (t.period.value.count() % 1000 != 0)
      fail(n["period"], "key 'period': must be a whole number of microseconds");
    t.priority = {0, t.mark};
    if (n["priority"]) {
      auto p = integer(n["priority"], "priority", 0, 48);
      t.priority = {int(p.value), p.mark};
    }
    t.watchdog = {10.0, t.mark};
    if (n["watchdog"]) {
      auto s = scalar(n["watchdog"], "watchdog");
      auto d = parse_iec_real(s.value);
      if (!d || *d < 0)
        fail(n["watchdog"],
             "key 'watchdog': '" + s.value + "' is not a multiple of the period >= 0 (0 = off)");
      if (*d > 0 && *d < 1)
        fail(n["watchdog"], "key 'watchdog': a multiple below 1 would trip on every scan");
      if (*d > kMaxWatchdog)
        fail(n["watchdog"], "key 'watchdog': " + s.value + " out of range [1, " +
                                std::to_string(int(kMaxWatchdog)) + "] (0 = off)");
      t.watchdog = {*d, s.mark};
    }
    const YAML::Node progs = require(n, "programs", "task '" + t.name.value + "'");
    if (!progs.IsSequence()) fail(progs, "key 'programs' must be a list of program names");
    for (const auto& p : progs) t.programs.push_back(scalar(p, "programs"));
    return t;
  }

  RetainConfig retain(const YAML::Node& n, const io::ImageSizes& image) const {
    RetainConfig r;
    r.present = true;
    r.mark = mark_of(n);
    expect_map(n, "retain");
    check_keys(n, {"file", "save_every", "memory", "on_damage"}, "retain");
    r.file = scalar(require(n, "file", "retain"), "file");
    if (r.file.value.empty()) fail(n["file"], "key 'file': names no file");
    // Relative to the config's folder: the cell keeps its file wherever it
    // is started from.
    r.path = in_folder(r.file.value);
    r.save_every.mark = r.mark;
    if (n["save_every"]) {
      r.save_every = time(n["save_every"], "save_every");
      if (r.save_every.value < kMinSaveEvery || r.save_every.value > kMaxSaveEvery)
        fail(n["save_every"], "key 'save_every': " + format_iec_time(r.save_every.value) +
                                  " out of range [" + format_iec_time(kMinSaveEvery) + ", " +
                                  format_iec_time(kMaxSaveEvery) + "]");
    }
    if (const auto m = n["memory"]) {
      if (!m.IsSequence())
        fail(m,
             "key 'memory' must be a list of %M addresses or ranges (e.g. [\"%MB0..%MB15\", "
             "%MD20])");
      for (const auto& item : m) r.memory.push_back(memory_range(item, image));
    }
    if (const auto d = n["on_damage"]) {
      const auto s = scalar(d, "on_damage");
      if (s.value != "cold" && s.value != "stop")
        fail(d, "key 'on_damage': '" + s.value + "' is not cold or stop");
      r.on_damage = {s.value == "cold" ? RetainOnDamage::Cold : RetainOnDamage::Stop, s.mark};
    }
    return r;
  }

  HmiConfig hmi(const YAML::Node& n) const {
    HmiConfig h;
    h.present = true;
    h.mark = mark_of(n);
    expect_map(n, "hmi");
    check_keys(n,
               {"url", "prefix", "rate", "publish", "writable", "forceable", "stop_commands",
                "key_file", "user", "netns", "web"},
               "hmi");
    h.url.mark = h.prefix.mark = h.rate.mark = h.stop_commands.mark = h.mark;
    if (n["url"]) {
      h.url = scalar(n["url"], "url");
      const std::string& u = h.url.value;
      // The rest (address, port, options) is checked by the bridge, which
      // parses it (hmi-bridge lcm_url.hpp) and names this key in its error.
      if (u.rfind("udpm://", 0) != 0 && u.rfind("memq://", 0) != 0)
        fail(n["url"], "key 'url': '" + u + "' is not an LCM url (udpm:// or memq://)");
    }
    if (n["prefix"]) {
      h.prefix = scalar(n["prefix"], "prefix");
      // LCM channel names: at most 63 characters; ours add up to 7 ("_VALUES").
      const std::string& p = h.prefix.value;
      if (p.empty() || p.size() > 40 ||
          p.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_") !=
              std::string::npos)
        fail(n["prefix"], "key 'prefix': '" + p + "' is not 1 to 40 letters, digits or '_'");
    }
    if (n["rate"]) {
      auto r = integer(n["rate"], "rate", 1, kMaxHmiRate);
      h.rate = {int(r.value), r.mark};
    }
    auto patterns = [&](const char* key, std::vector<Item<std::string>>& out) {
      const YAML::Node l = n[key];
      if (!l) return;
      if (!l.IsSequence())
        fail(l, std::string("key '") + key + "' must be a list of patterns (e.g. [\"Cell.*\"])");
      for (const auto& p : l) {
        out.push_back(scalar(p, key));
        if (out.back().value.empty()) fail(p, std::string("key '") + key + "': an empty pattern");
      }
    };
    patterns("publish", h.publish);
    patterns("writable", h.writable);
    patterns("forceable", h.forceable);
    if (const auto b = n["stop_commands"]) {
      auto s = scalar(b, "stop_commands");
      if (s.value != "true" && s.value != "false")
        fail(b, "key 'stop_commands': '" + s.value + "' is not true or false");
      h.stop_commands = {s.value == "true", s.mark};
    }
    if (n["key_file"]) {
      h.key_file = scalar(n["key_file"], "key_file");
      if (h.key_file.value.empty()) fail(n["key_file"], "key 'key_file': names no file");
      h.key_path = in_folder(h.key_file.value);
    }
    h.user.mark = h.netns.mark = h.mark;
    if (n["user"]) {
      h.user = scalar(n["user"], "user");
      if (h.user.value.empty()) fail(n["user"], "key 'user': names no user");
    }
    if (n["netns"]) {
      h.netns = scalar(n["netns"], "netns");
      const std::string& ns = h.netns.value;
      // A name under /var/run/netns (as `ip netns` makes them), or a path.
      if (ns.empty() || (ns[0] != '/' && ns.find('/') != std::string::npos))
        fail(n["netns"],
             "key 'netns': '" + ns + "' is neither a name of `ip netns list` nor an absolute path");
    }
    if (n["web"]) h.web = web(n["web"], h);
    return h;
  }

  // hmi: web: the browser HMI (docs/config.md). The address and the login
  // are checked here, where their line is known.
  WebConfig web(const YAML::Node& n, const HmiConfig& h) const {
    WebConfig w;
    w.present = true;
    w.mark = mark_of(n);
    expect_map(n, "web");
    check_keys(n, {"address", "port", "read_only", "login", "tls"}, "web");
    w.address.mark = w.port.mark = w.read_only.mark = w.login.mark = w.mark;
    if (n["address"]) {
      w.address = scalar(n["address"], "address");
      if (!ip_address(w.address.value))
        fail(n["address"],
             "key 'address': '" + w.address.value + "' is not an IPv4 or IPv6 address");
    }
    if (n["port"]) {
      auto p = integer(n["port"], "port", 1, 65535);
      w.port = {int(p.value), p.mark};
    }
    if (const auto b = n["read_only"]) {
      auto s = scalar(b, "read_only");
      if (s.value != "true" && s.value != "false")
        fail(b, "key 'read_only': '" + s.value + "' is not true or false");
      w.read_only = {s.value == "true", s.mark};
    }
    if (const auto t = n["tls"]) {
      // The files are read and checked by plcrun at the bridge's start
      // (hmi-bridge/src/host/tls_files.cpp), which reports at these lines.
      expect_map(t, "tls");
      check_keys(t, {"cert", "key"}, "tls");
      w.tls = true;
      w.tls_cert = scalar(require(t, "cert", "tls"), "cert");
      w.tls_key = scalar(require(t, "key", "tls"), "key");
      if (w.tls_cert.value.empty()) fail(t["cert"], "key 'cert': names no file");
      if (w.tls_key.value.empty()) fail(t["key"], "key 'key': names no file");
      w.tls_cert_path = in_folder(w.tls_cert.value);
      w.tls_key_path = in_folder(w.tls_key.value);
    }
    const YAML::Node l = require(n, "login", "web");
    w.login = scalar(l, "login");
    const std::string& login = w.login.value;
    if (login == "none") {
      if (!is_loopback(w.address.value))
        fail(l, "key 'login': none is allowed on a loopback address only (the address is " +
                    w.address.value + ")");
    } else if (login == "key") {
      if (h.key_path.empty())
        fail(l, "key 'login': key needs the hmi: key_file (its 64 hex digits are the password)");
    } else if (!valid_password_hash(login)) {
      fail(l,
           "key 'login': not none, key or a password hash "
           "pbkdf2-sha256$ITERATIONS$SALT_HEX$HASH_HEX (make one with plchmi --hash-password)");
    }
    return w;
  }

  static bool ip_address(const std::string& a) {
    unsigned char buf[sizeof(in6_addr)];
    return inet_pton(AF_INET, a.c_str(), buf) == 1 || inet_pton(AF_INET6, a.c_str(), buf) == 1;
  }
  static bool is_loopback(const std::string& a) {
    unsigned char buf[sizeof(in6_addr)];
    if (inet_pton(AF_INET, a.c_str(), buf) == 1) return buf[0] == 127;
    return a == "::1";
  }

  // pbkdf2-sha256$ITERATIONS$SALT_HEX$HASH_HEX: the shape only (plchmi
  // checks a password against it).
  static bool valid_password_hash(const std::string& s) {
    std::vector<std::string> parts;
    std::size_t from = 0;
    for (;;) {
      const auto d = s.find('$', from);
      parts.push_back(s.substr(from, d - from));
      if (d == std::string::npos) break;
      from = d + 1;
    }
    auto hex = [](const std::string& x, std::size_t min, std::size_t max) {
      return x.size() >= min && x.size() <= max && x.size() % 2 == 0 &&
             x.find_first_not_of("0123456789abcdefABCDEF") == std::string::npos;
    };
    if (parts.size() != 4 || parts[0] != "pbkdf2-sha256") return false;
    const std::string& it = parts[1];
    if (it.empty() || it.size() > 8 || it.find_first_not_of("0123456789") != std::string::npos)
      return false;
    const long n = std::stol(it);
    return n >= 1000 && n <= 10'000'000 && hex(parts[2], 16, 128) && hex(parts[3], 32, 64);
  }

  // "%MW10" (its bytes) or "%MB0..%MB15" (inclusive), inside the %M image.
  RetainMemoryRange memory_range(const YAML::Node& n, const io::ImageSizes& image) const {
    const auto s = scalar(n, "memory");
    const auto dots = s.value.find("..");
    auto one = [&](const std::string& text) {
      auto a = io::parse_iec_address(text);
      if (!a.address) fail(n, "key 'memory': " + a.error);
      if (a.address->area != io::Area::Memory)
        fail(n, "key 'memory': " + text + " is not a %M address (only memory is retained)");
      return *a.address;
    };
    const io::IecAddress first = one(s.value.substr(0, dots));
    const io::IecAddress last = dots == std::string::npos ? first : one(s.value.substr(dots + 2));
    RetainMemoryRange r{first.byte, 0, s.mark};
    const std::size_t end = last.byte + last.width_bytes();
    if (end <= first.byte) fail(n, "key 'memory': '" + s.value + "' ends before it starts");
    r.count = end - first.byte;
    if (end > image.memory)
      fail(n, "key 'memory': '" + s.value + "' lies outside the %M image (" +
                  std::to_string(image.memory) + " bytes; see image: memory)");
    return r;
  }

  ProgramConfig program(const YAML::Node& n) {
    ProgramConfig p;
    p.mark = mark_of(n);
    expect_map(n, "a program");
    check_keys(n, {"name", "type", "bind", "init"}, "program");
    p.name = scalar(require(n, "name", "program"), "name");
    p.type = scalar(require(n, "type", "program '" + p.name.value + "'"), "type");
    if (n["bind"]) p.bind = string_map(n["bind"], "bind");
    if (n["init"]) p.init = string_map(n["init"], "init");
    return p;
  }

  PluginConfig plugin(const YAML::Node& n) {
    PluginConfig p;
    p.mark = mark_of(n);
    expect_map(n, "a plugin");
    check_keys(n, {"name", "type", "params"}, "plugin");
    p.name = scalar(require(n, "name", "plugin"), "name");
    p.type = n["type"] ? scalar(n["type"], "type") : Item<std::string>{p.name.value, p.name.mark};
    if (n["params"]) p.params = params(n["params"], "params");
    return p;
  }

  DeviceConfig device(const YAML::Node& n) {
    DeviceConfig d;
    d.mark = mark_of(n);
    expect_map(n, "a device");
    check_keys(n, {"name", "plugin", "model", "input", "output", "task", "params"}, "device");
    d.name = scalar(require(n, "name", "device"), "name");
    const std::string what = "device '" + d.name.value + "'";
    d.plugin = scalar(require(n, "plugin", what), "plugin");
    if (n["model"]) d.model = scalar(n["model"], "model");
    d.input = n["input"] ? scalar(n["input"], "input") : Item<std::string>{"", d.mark};
    d.output = n["output"] ? scalar(n["output"], "output") : Item<std::string>{"", d.mark};
    if (n["task"]) d.task = scalar(n["task"], "task");
    if (n["params"]) d.params = params(n["params"], "params");
    return d;
  }

  template <class T>
  void unique_names(const std::vector<T>& v, const std::string& what) const {
    std::set<std::string> seen;
    for (const auto& x : v)
      if (!seen.insert(x.name.value).second)
        fail(x.name.mark, "duplicate " + what + " name '" + x.name.value + "'");
  }

  void cross_check(const CellConfig& c) const {
    unique_names(c.tasks, "task");
    unique_names(c.programs, "program");
    unique_names(c.plugins, "plugin");
    unique_names(c.devices, "device");
    std::map<std::string, std::string> program_task;
    for (const auto& t : c.tasks) {
      for (const auto& p : t.programs) {
        bool found = false;
        for (const auto& pc : c.programs) found |= pc.name.value == p.value;
        if (!found)
          fail(p.mark, "task '" + t.name.value + "' runs unknown program '" + p.value +
                           "' (declare it under 'programs')");
        auto [it, fresh] = program_task.emplace(p.value, t.name.value);
        if (!fresh)
          fail(p.mark, "program '" + p.value + "' is already run by task '" + it->second + "'");
      }
    }
    for (const auto& d : c.devices) {
      bool found = false;
      for (const auto& p : c.plugins) found |= p.name.value == d.plugin.value;
      if (!found)
        fail(d.plugin.mark, "device '" + d.name.value + "' uses unknown plugin '" + d.plugin.value +
                                "' (declare it under 'plugins')");
      if (!d.task.value.empty()) {
        bool t_found = false;
        for (const auto& t : c.tasks) t_found |= t.name.value == d.task.value;
        if (!t_found)
          fail(d.task.mark,
               "device '" + d.name.value + "' names unknown task '" + d.task.value + "'");
      }
    }
  }

 private:
  std::string file_;
  std::string folder_;
};

}  // namespace

CellConfig parse_cell_config(const std::string& text, const std::string& file_name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file_name, {e.mark.line + 1, e.mark.column + 1},
                      "YAML syntax error: " + e.msg);
  }
  Loader l(file_name);
  try {
    return l.load(root);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file_name, {e.mark.line + 1, e.mark.column + 1}, e.msg);
  }
}

CellConfig load_cell_config(const std::string& path) {
  if (const std::string why = readable_file_problem(path); !why.empty())
    throw ConfigError(path, {}, why);
  std::ifstream in(path);
  if (!in) throw ConfigError(path, {}, "cannot open the config file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_cell_config(ss.str(), path);
}

}  // namespace plc
