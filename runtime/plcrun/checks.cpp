#include "checks.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "plc/iec_literal.hpp"

namespace plc {
namespace {

Mark mark_of(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  if (m.line < 0) return {};
  return {m.line + 1, m.column + 1};
}

const char* kind_name(CheckKind k) {
  switch (k) {
    case CheckKind::Always:
      return "always";
    case CheckKind::AtEnd:
      return "at_end";
    case CheckKind::Eventually:
      return "eventually";
  }
  return "?";
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// Shortest text that reads back as the same double (JSON has no inf/NaN:
// they become null).
std::string json_number(double d) {
  if (!std::isfinite(d)) return "null";
  char b[40];
  std::snprintf(b, sizeof b, "%.15g", d);
  if (std::strtod(b, nullptr) != d) std::snprintf(b, sizeof b, "%.17g", d);
  return b;
}

double seconds(TIME t) { return std::chrono::duration<double>(t).count(); }

class ChecksLoader {
 public:
  explicit ChecksLoader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Node& n, const std::string& msg) const {
    throw ConfigError(file_, mark_of(n), msg);
  }

  Item<std::string> scalar(const YAML::Node& v, const std::string& key) const {
    if (!v.IsScalar()) fail(v, "key '" + key + "' must be a single value");
    return {v.Scalar(), mark_of(v)};
  }

  ChecksFile load(const YAML::Node& root) {
    ChecksFile f;
    f.file = file_;
    if (!root || !root.IsMap())
      throw ConfigError(file_, {1, 1}, "the checks file must be a mapping");
    const YAML::Node list = root["checks"];
    if (!list) fail(root, "missing key 'checks' (a list of checks)");
    if (!list.IsSequence()) fail(list, "key 'checks' must be a list (items start with '- ')");
    std::set<std::string> names;
    for (const auto& item : list) {
      if (!item.IsMap())
        fail(item, "a check must be a mapping (name:, always:|at_end:|eventually:)");
      CheckSpec c;
      int kinds = 0;
      for (auto it = item.begin(); it != item.end(); ++it) {
        const std::string key = it->first.Scalar();
        const YAML::Node v = it->second;
        if (key == "name") {
          c.name = scalar(v, key);
        } else if (key == "severity") {
          const auto s = scalar(v, key);
          if (s.value == "error") {
            c.severity = CheckSeverity::Error;
          } else if (s.value == "warning") {
            c.severity = CheckSeverity::Warning;
          } else {
            fail(v, "key 'severity': '" + s.value + "' is not error or warning");
          }
        } else if (key == "always" || key == "at_end" || key == "eventually") {
          ++kinds;
          c.kind = key == "always"   ? CheckKind::Always
                   : key == "at_end" ? CheckKind::AtEnd
                                     : CheckKind::Eventually;
          c.condition = scalar(v, key);
        } else if (key == "grace") {
          const auto s = scalar(v, key);
          const auto t = parse_iec_time(s.value);
          if (!t || t->count() < 0)
            fail(v, "key 'grace': '" + s.value + "' is not a duration (e.g. 100ms)");
          c.grace = *t;
        } else {
          fail(it->first, "unknown key '" + key +
                              "' in a check (expected one of: always, at_end, eventually, grace, "
                              "name, severity)");
        }
      }
      if (c.name.value.empty()) fail(item, "a check needs a 'name'");
      if (kinds != 1)
        fail(item,
             "check '" + c.name.value + "' needs exactly one of always:, at_end:, eventually:");
      if (c.grace.count() > 0 && c.kind != CheckKind::Always)
        fail(item["grace"], "key 'grace' applies to always: checks only");
      if (!names.insert(c.name.value).second)
        throw ConfigError(file_, c.name.mark, "duplicate check name '" + c.name.value + "'");
      f.checks.push_back(std::move(c));
    }
    if (const YAML::Node outs = root["outputs"]) {
      if (!outs.IsSequence()) fail(outs, "key 'outputs' must be a list of variable paths");
      for (const auto& o : outs) f.outputs.push_back(scalar(o, "outputs"));
    }
    return f;
  }

 private:
  std::string file_;
};

}  // namespace

ChecksFile parse_checks_file(const std::string& text, const std::string& file_name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file_name, {e.mark.line + 1, e.mark.column + 1},
                      "YAML syntax error: " + e.msg);
  }
  try {
    return ChecksLoader(file_name).load(root);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file_name, {e.mark.line + 1, e.mark.column + 1}, e.msg);
  }
}

ChecksFile load_checks_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path, {}, "cannot open the checks file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_checks_file(ss.str(), path);
}

ScenarioChecks::ScenarioChecks(Runtime& rt, ChecksFile spec) : rt_(rt), file_(spec.file) {
  for (auto& c : spec.checks) {
    std::string err;
    auto cond =
        debug::Condition::compile(c.condition.value, rt.vars(), rt.image(), rt.byte_order(), err);
    if (!cond)
      throw ConfigError(file_, c.condition.mark,
                        "check '" + c.name.value + "': " + err +
                            " (plcrun CONFIG --list-vars lists the variables)");
    Check check{std::move(c), std::move(*cond)};
    checks_.push_back(std::move(check));
  }
  for (const auto& o : spec.outputs) {
    const VarInfo* v = rt.vars().find(o.value);
    if (!v)
      throw ConfigError(
          file_, o.mark,
          "output '" + o.value + "' is not a variable (plcrun CONFIG --list-vars lists them)");
    Output out;
    out.path = o.value;
    out.var = v;
    outputs_.push_back(std::move(out));
  }
  rt.add_scan_observer(
      [this](const TaskRuntime& t, const ScanContext& ctx) { after_scan(t, ctx); });
}

void ScenarioChecks::after_scan(const TaskRuntime& t, const ScanContext& ctx) {
  ++scans_;
  last_time_ = ctx.now;
  const int task = static_cast<int>(t.order);
  for (auto& c : checks_) {
    if (c.spec.kind == CheckKind::AtEnd) continue;
    if (c.cond.task() >= 0 && c.cond.task() != task) continue;
    const bool holds = c.cond.holds();
    if (c.spec.kind == CheckKind::Eventually) {
      c.held = c.held || holds;
      continue;
    }
    if (holds) {
      c.violation_since.reset();
      continue;
    }
    ++c.violating_scans;
    if (!c.violation_since) c.violation_since = ctx.now;
    // A violation counts once it has lasted longer than the grace time
    // (0: at once); the failure is located where it started to count.
    if (!c.failed && ctx.now - *c.violation_since >= c.spec.grace) {
      c.failed = true;
      c.first_fail_scan = scans_;
      c.first_fail_time = ctx.now;
    }
  }
  for (auto& o : outputs_) {
    const double v = debug::read_value(*o.var).as_real();
    if (!o.seen || v < o.min) o.min = v;
    if (!o.seen || v > o.max) o.max = v;
    o.seen = true;
  }
}

void ScenarioChecks::finish() {
  for (auto& c : checks_) {
    if (c.spec.kind == CheckKind::AtEnd && !c.cond.holds()) c.failed = true;
    if (c.spec.kind == CheckKind::Eventually && !c.held) c.failed = true;
    if (c.failed && c.spec.kind != CheckKind::Always) {
      c.first_fail_scan = scans_;
      c.first_fail_time = last_time_;
    }
  }
  for (auto& o : outputs_) {
    o.final_text = VarRegistry::format(*o.var);
    o.final_value = debug::read_value(*o.var).as_real();
    if (!o.seen) o.min = o.max = o.final_value;
  }
  // FNV-1a over every variable's bytes (strings by their text): two runs of
  // one scenario must agree on all of the cell's state, not only on what
  // the checks look at.
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  for (const VarInfo& v : rt_.vars().all()) {
    mix(v.path.data(), v.path.size());
    if (v.type == VarType::STRING) {
      const std::string s = VarRegistry::format(v);
      mix(s.data(), s.size());
    } else {
      alignas(8) unsigned char buf[16] = {};
      VarRegistry::read(v, buf);
      mix(buf, size_of(v.type));
    }
  }
  state_digest_ = h;
}

bool ScenarioChecks::passed() const {
  for (const auto& c : checks_)
    if (c.failed && c.spec.severity == CheckSeverity::Error) return false;
  return true;
}

std::string ScenarioChecks::json(const std::string& stop_reason) const {
  std::string s = "{\"cell\":" + json_string(rt_.cell_name());
  s += ",\"passed\":" + std::string(passed() ? "true" : "false");
  s += ",\"scans\":" + std::to_string(scans_);
  s += ",\"sim_time_s\":" + json_number(seconds(last_time_));
  s += ",\"stop_reason\":" + json_string(stop_reason);
  char digest[24];
  std::snprintf(digest, sizeof digest, "%016llx", static_cast<unsigned long long>(state_digest_));
  s += ",\"state_digest\":\"" + std::string(digest) + "\"";
  s += ",\"checks\":[";
  for (std::size_t i = 0; i < checks_.size(); ++i) {
    const Check& c = checks_[i];
    if (i) s += ",";
    s += "{\"name\":" + json_string(c.spec.name.value);
    s += ",\"kind\":\"" + std::string(kind_name(c.spec.kind)) + "\"";
    s += ",\"severity\":\"" +
         std::string(c.spec.severity == CheckSeverity::Error ? "error" : "warning") + "\"";
    s += ",\"condition\":" + json_string(c.spec.condition.value);
    s += ",\"passed\":" + std::string(c.failed ? "false" : "true");
    if (c.failed) {
      s += ",\"first_fail_scan\":" + std::to_string(c.first_fail_scan);
      s += ",\"first_fail_time_s\":" + json_number(seconds(c.first_fail_time));
    }
    if (c.spec.kind == CheckKind::Always)
      s += ",\"violating_scans\":" + std::to_string(c.violating_scans);
    s += "}";
  }
  s += "],\"outputs\":{";
  for (std::size_t i = 0; i < outputs_.size(); ++i) {
    const Output& o = outputs_[i];
    if (i) s += ",";
    s += json_string(o.path) + ":{\"final\":" + json_number(o.final_value) +
         ",\"text\":" + json_string(o.final_text) + ",\"min\":" + json_number(o.min) +
         ",\"max\":" + json_number(o.max) + "}";
  }
  s += "},\"timing\":{\"wall_s\":" + json_number(rt_.wall_seconds()) + "}}\n";
  return s;
}

std::string ScenarioChecks::failures_text() const {
  std::string s;
  for (const auto& c : checks_) {
    if (!c.failed) continue;
    char b[64];
    std::snprintf(b, sizeof b, "%.6f", seconds(c.first_fail_time));
    s += std::string("check ") + (c.spec.severity == CheckSeverity::Error ? "FAILED" : "warning") +
         ": " + c.spec.name.value + " (" + kind_name(c.spec.kind) + " " + c.spec.condition.value +
         ") at scan " + std::to_string(c.first_fail_scan) + ", t=" + b + " s\n";
  }
  return s;
}

}  // namespace plc
