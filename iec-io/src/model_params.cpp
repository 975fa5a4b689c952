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

namespace {

// The flow text of a YAML list of numbers, nested at most `depth` deep.
class ListParser {
 public:
  ListParser(const std::string& key, const std::string& text) : key_(key), s_(text) {}

  // A number or a bracketed list of numbers.
  std::vector<double> flat() {
    std::vector<double> out;
    skip();
    if (peek() != '[') {
      out.push_back(number());
    } else {
      ++i_;
      items([&] { out.push_back(number()); });
    }
    end();
    return out;
  }

  // A number, a list of numbers (one row) or a list of such lists.
  std::vector<std::vector<double>> rows() {
    std::vector<std::vector<double>> out;
    skip();
    if (peek() != '[') {
      out.push_back({number()});
    } else {
      ++i_;
      skip();
      if (peek() == '[') {
        items([&] {
          skip();
          if (peek() != '[') fail("a row of a matrix must be a list, e.g. [1, 0]");
          ++i_;
          std::vector<double> row;
          items([&] { row.push_back(number()); });
          out.push_back(std::move(row));
        });
      } else {
        std::vector<double> row;
        items([&] { row.push_back(number()); });
        out.push_back(std::move(row));
      }
    }
    end();
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw ParamError(key_, why + " (in '" + s_ + "')");
  }
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skip() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n')) ++i_;
  }
  // Items separated by commas up to the closing bracket (the opening one
  // has been consumed); [] is an empty list.
  template <class F>
  void items(F item) {
    skip();
    if (peek() == ']') {
      ++i_;
      return;
    }
    for (;;) {
      item();
      skip();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() == ']') {
        ++i_;
        return;
      }
      fail("expected ',' or ']' after '" + s_.substr(0, i_) + "'");
    }
  }
  double number() {
    skip();
    std::size_t j = i_;
    while (j < s_.size() && s_[j] != ',' && s_[j] != ']' && s_[j] != ' ' && s_[j] != '[') ++j;
    double d = 0;
    const char* b = s_.data() + i_;
    if (*b == '+') ++b;  // from_chars takes no plus sign; YAML does
    auto [p, ec] = std::from_chars(b, s_.data() + j, d);
    if (j == i_ || ec != std::errc() || p != s_.data() + j || !std::isfinite(d))
      fail("'" + s_.substr(i_, j - i_) + "' is not a finite number");
    i_ = j;
    return d;
  }
  void end() {
    skip();
    if (i_ != s_.size()) fail("unexpected '" + s_.substr(i_) + "' after the list");
  }

  const std::string& key_;
  const std::string& s_;
  std::size_t i_ = 0;
};

}  // namespace

std::optional<std::vector<double>> ModelParams::get_list(const std::string& key) const {
  const std::string* v = find(key);
  if (!v) return std::nullopt;
  return ListParser(key, *v).flat();
}

std::optional<std::vector<std::vector<double>>> ModelParams::get_matrix(
    const std::string& key) const {
  const std::string* v = find(key);
  if (!v) return std::nullopt;
  return ListParser(key, *v).rows();
}

bool ModelParams::has_group(const std::string& prefix) const {
  auto it = values_.lower_bound(prefix);
  for (; it != values_.end() && it->first.compare(0, prefix.size(), prefix) == 0; ++it)
    if (it->first.size() == prefix.size() || it->first[prefix.size()] == '.') return true;
  return false;
}

void ModelParams::reject_unknown() const {
  for (const auto& [k, _] : values_)
    if (!used_.count(k)) throw ParamError(k, "unknown parameter '" + k + "'");
}

}  // namespace plc::io
