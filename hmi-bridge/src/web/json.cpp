#include "plc/hmi/web/json.hpp"

#include <cmath>
#include <cstdio>
#include <unordered_map>

namespace plc::hmi::web {

namespace {

// Length of the valid UTF-8 sequence at s[i], 0 when it is not one.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  std::size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) >> 6) != 2) return 0;
  if (n == 2 && c < 0xc2) return 0;  // overlong
  return n;
}

void key(std::string& out, const char* k) {
  out += '"';
  out += k;
  out += "\":";
}

void field(std::string& out, const char* k, std::string_view v) {
  key(out, k);
  append_string(out, v);
  out += ',';
}

void field(std::string& out, const char* k, std::int64_t v) {
  key(out, k);
  out += std::to_string(v);
  out += ',';
}

// LCM's boolean is an int8_t.
void flag(std::string& out, const char* k, bool v) {
  key(out, k);
  out += v ? "true," : "false,";
}

// Closes an object or array whose last member left a ','.
void close(std::string& out, char c) {
  if (out.back() == ',')
    out.back() = c;
  else
    out += c;
}

void alarm_members(std::string& out, const softplc_hmi::alarm_t& a) {
  field(out, "source", a.source);
  field(out, "text", a.text);
  field(out, "kind", a.kind);
  flag(out, "active", a.active != 0);
  field(out, "from", a.from_state);
  field(out, "to", a.to_state);
  field(out, "task", a.task);
  field(out, "scan", a.scan);
  field(out, "plc_ns", a.plc_time_ns);
  field(out, "utime", a.utime);
}

}  // namespace

void append_string(std::string& out, std::string_view s) {
  out += '"';
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += char(c);
      ++i;
    } else if (c < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
      ++i;
    } else if (const std::size_t n = utf8_length(s, i)) {
      out.append(s.substr(i, n));
      i += n;
    } else {
      out += "\xef\xbf\xbd";
      ++i;
    }
  }
  out += '"';
}

void append_number(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  out += b;
}

std::string description_json(const softplc_hmi::cell_description_t& d, bool read_only,
                             const std::string& login) {
  std::string out = "{";
  field(out, "t", "desc");
  field(out, "cell", d.cell);
  field(out, "layout", d.layout_hash);
  flag(out, "stop_commands", d.stop_commands_allowed != 0);
  flag(out, "read_only", read_only);
  field(out, "login", login);
  key(out, "vars");
  out += '[';
  for (const auto& v : d.vars) {
    out += '{';
    field(out, "p", v.path);
    field(out, "ty", v.type);
    field(out, "a", v.address);
    field(out, "k", v.task);
    flag(out, "pub", v.published != 0);
    flag(out, "w", v.writable != 0);
    flag(out, "f", v.forceable != 0);
    close(out, '}');
    out += ',';
  }
  close(out, ']');
  out += '}';
  return out;
}

std::string values_json(const softplc_hmi::values_t& v, const softplc_hmi::trace_sample_t& t) {
  std::unordered_map<int, double> number;
  number.reserve(t.index.size());
  for (std::size_t i = 0; i < t.index.size() && i < t.value.size(); ++i)
    number[t.index[i]] = t.value[i];
  std::string out = "{";
  field(out, "t", "values");
  field(out, "task", v.task);
  field(out, "scan", v.scan);
  field(out, "plc_ns", v.plc_time_ns);
  field(out, "scan_utime", v.scan_utime);
  field(out, "utime", v.utime);
  flag(out, "full", v.full != 0);
  key(out, "v");
  out += '[';
  for (const auto& x : v.values) {
    out += '[';
    out += std::to_string(x.index);
    out += ',';
    append_string(out, x.text);
    out += ',';
    const auto it = number.find(x.index);
    append_number(out, it == number.end() ? NAN : it->second);
    out += "],";
  }
  close(out, ']');
  out += '}';
  return out;
}

std::string stats_json(const softplc_hmi::stats_t& s, const std::string& web_counters) {
  std::string out = "{";
  field(out, "t", "stats");
  field(out, "utime", s.utime);
  field(out, "cell", s.cell);
  key(out, "tasks");
  out += '[';
  for (const auto& k : s.tasks) {
    out += '{';
    field(out, "name", k.name);
    field(out, "period_ns", k.period_ns);
    field(out, "scans", k.scans);
    field(out, "overruns", k.overruns);
    field(out, "min_ns", k.scan_ns_min);
    field(out, "avg_ns", k.scan_ns_avg);
    field(out, "max_ns", k.scan_ns_max);
    field(out, "stop", k.stop_reason);
    close(out, '}');
    out += ',';
  }
  close(out, ']');
  out += ',';
  key(out, "bridge");
  out += '{';
  field(out, "published", s.published);
  field(out, "dropped", s.dropped);
  field(out, "commands", s.commands);
  field(out, "refused", s.refused);
  field(out, "malformed", s.malformed);
  close(out, '}');
  out += ',';
  key(out, "web");
  out += web_counters;
  out += '}';
  return out;
}

std::string diagnostics_json(const softplc_hmi::diagnostics_t& d) {
  std::string out = "{";
  field(out, "t", "diag");
  field(out, "utime", d.utime);
  key(out, "devices");
  out += '[';
  for (const auto& v : d.devices) {
    out += '{';
    field(out, "name", v.name);
    field(out, "plugin", v.plugin);
    field(out, "task", v.task);
    field(out, "input", v.input);
    field(out, "output", v.output);
    field(out, "in_bytes", std::int64_t(v.in_bytes));
    field(out, "out_bytes", std::int64_t(v.out_bytes));
    field(out, "state", v.state);
    field(out, "diag", v.diagnostics);
    field(out, "changes", v.changes);
    close(out, '}');
    out += ',';
  }
  close(out, ']');
  out += ',';
  key(out, "alarms");
  out += '[';
  for (const auto& a : d.alarms) {
    out += '{';
    alarm_members(out, a);
    close(out, '}');
    out += ',';
  }
  close(out, ']');
  out += '}';
  return out;
}

std::string alarm_json(const softplc_hmi::alarm_t& a, std::int64_t id, bool acked) {
  std::string out = "{";
  field(out, "t", "alarm");
  field(out, "id", id);
  flag(out, "acked", acked);
  alarm_members(out, a);
  close(out, '}');
  return out;
}

std::string reply_json(const softplc_hmi::reply_t& r) {
  std::string out = "{";
  flag(out, "ok", r.ok != 0);
  field(out, "refusal", r.refusal);
  field(out, "text", r.text);
  key(out, "values");
  out += '[';
  for (const auto& v : r.values) {
    out += '{';
    field(out, "path", v.path);
    field(out, "type", v.type);
    field(out, "address", v.address);
    field(out, "text", v.text);
    field(out, "error", v.error);
    flag(out, "forced", v.forced != 0);
    close(out, '}');
    out += ',';
  }
  close(out, ']');
  out += '}';
  return out;
}

}  // namespace plc::hmi::web
