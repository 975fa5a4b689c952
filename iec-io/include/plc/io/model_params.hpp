// Parameters of a device model or plugin, as given under `params:` in the
// cell config. Kept free of YAML so models do not depend on the config
// parser; the loader turns a ParamError into `file:line:column: message`
// pointing at the offending key.
//
// Values are text. A nested mapping in the config arrives flattened into
// dotted keys (`u1: {type: INT}` is the key "u1.type"), a YAML list as its
// flow text ("[1, 2]", "[[1, 0], [0, 1]]"), which get_list/get_matrix read.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "plc/types.hpp"

namespace plc::io {

struct ParamError : std::runtime_error {
  ParamError(std::string key_, const std::string& msg)
      : std::runtime_error(msg), key(std::move(key_)) {}
  std::string key;  // the offending key ("" = the params block itself)
};

class ModelParams {
 public:
  void set(const std::string& key, const std::string& value) { values_[key] = value; }
  [[nodiscard]] bool has(const std::string& key) const { return values_.count(key) != 0; }

  // Typed getters: return the default when absent, throw ParamError when the
  // value does not parse or lies outside [min, max]. Each getter marks the
  // key used. Every number a model takes states its range: a value the
  // model cannot represent or compute with (a weight beyond a DINT, a
  // negative time constant) is a config error naming the key, never a
  // wrapped value or undefined behaviour later.
  double get_double(const std::string& key, double def, double min, double max) const;
  std::int64_t get_int(const std::string& key, std::int64_t def, std::int64_t min,
                       std::int64_t max) const;
  bool get_bool(const std::string& key, bool def) const;
  // "T#2s", "20ms", "1.5s"
  TIME get_time(const std::string& key, TIME def, TIME min, TIME max) const;
  std::string get_string(const std::string& key, const std::string& def) const;
  // A file the parameter names (a GSDML file, a capture): a relative path
  // is taken from folder(), the config file's folder (plc/config_path.hpp);
  // "" when absent.
  std::string get_path(const std::string& key) const;

  // The folder of the config that gave these parameters ("" = the current
  // directory: parameters not read from a file). The config loader sets it;
  // a copy of some of the parameters keeps it (set_folder(other.folder())).
  void set_folder(std::string folder) { folder_ = std::move(folder); }
  [[nodiscard]] const std::string& folder() const { return folder_; }
  // A list of finite numbers, "[1, 2.5, -3]", or a single number (a list of
  // one); nullopt when absent. Throws ParamError naming the key and the
  // position of an entry that is not a number.
  std::optional<std::vector<double>> get_list(const std::string& key) const;
  // A matrix as a list of rows, "[[1, 0], [0, 1]]"; a flat list is one row,
  // a single number is 1x1. Rows may differ in length here: the model says
  // what sizes it needs.
  std::optional<std::vector<std::vector<double>>> get_matrix(const std::string& key) const;
  // Whether `prefix` itself or any key below it ("prefix.x") is given. Marks
  // nothing as used.
  [[nodiscard]] bool has_group(const std::string& prefix) const;

  // Throws ParamError naming the first key no getter asked for: a typo in a
  // config must not pass silently. Models call this at the end of their
  // constructor.
  void reject_unknown() const;

  [[nodiscard]] const std::map<std::string, std::string>& values() const { return values_; }

 private:
  const std::string* find(const std::string& key) const;
  std::map<std::string, std::string> values_;
  mutable std::set<std::string> used_;
  std::string folder_;
};

}  // namespace plc::io
