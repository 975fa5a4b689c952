#include "plc/io/model_params.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "plc/config_path.hpp"
#include "plc/iec_literal.hpp"

namespace plc::io {

const std::string* ModelParams::find(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) return nullptr;
  used_.insert(key);
  return &it->second;
}

namespace {

std::string number_text(double d) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", d);
  return b;
}

[[noreturn]] void out_of_range(const std::string& key, const std::string& value,
                               const std::string& min, const std::string& max) {
  throw ParamError(key, "value " + value + " out of range [" + min + ", " + max + "]");
}

}  // namespace

double ModelParams::get_double(const std::string& key, double def, double min, double max) const {
  const std::string* v = find(key);
  if (!v) return def;
  double d = 0;
  auto [p, ec] = std::from_chars(v->data(), v->data() + v->size(), d);
  if (ec != std::errc() || p != v->data() + v->size() || !std::isfinite(d))
    throw ParamError(key, "expected a number, got '" + *v + "'");
  if (d < min || d > max) out_of_range(key, *v, number_text(min), number_text(max));
  return d;
}

std::int64_t ModelParams::get_int(const std::string& key, std::int64_t def, std::int64_t min,
                                  std::int64_t max) const {
  const std::string* v = find(key);
  if (!v) return def;
  auto parsed = parse_iec_integer(*v);
  if (!parsed) throw ParamError(key, "expected an integer, got '" + *v + "'");
  if (*parsed < min || *parsed > max)
    out_of_range(key, *v, std::to_string(min), std::to_string(max));
  return *parsed;
}

bool ModelParams::get_bool(const std::string& key, bool def) const {
  const std::string* v = find(key);
  if (!v) return def;
  if (*v == "true" || *v == "TRUE" || *v == "1") return true;
  if (*v == "false" || *v == "FALSE" || *v == "0") return false;
  throw ParamError(key, "expected true or false, got '" + *v + "'");
}

TIME ModelParams::get_time(const std::string& key, TIME def, TIME min, TIME max) const {
  const std::string* v = find(key);
  if (!v) return def;
  auto t = parse_iec_time(*v);
  if (!t) throw ParamError(key, "expected a duration (e.g. 20ms, T#1s500ms), got '" + *v + "'");
  if (*t < min || *t > max) out_of_range(key, *v, format_iec_time(min), format_iec_time(max));
  return *t;
}

std::string ModelParams::get_string(const std::string& key, const std::string& def) const {
  const std::string* v = find(key);
  return v ? *v : def;
}

std::string ModelParams::get_path(const std::string& key) const {
  const std::string* v = find(key);
  return v ? path_in_folder(folder_.empty() ? "." : folder_, *v) : std::string();
}

void ModelParams::reject_unknown() const {
  for (const auto& [k, _] : values_)
    if (!used_.count(k)) throw ParamError(k, "unknown parameter '" + k + "'");
}

}  // namespace plc::io
