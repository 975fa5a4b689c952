#include "plc/io/plugin.hpp"

namespace plc::io {

std::string Plugin::diagnostics(std::size_t device) const {
  return std::string(to_string(const_cast<Plugin*>(this)->link(device).live_state()));
}

PluginRegistry& PluginRegistry::instance() {
  static PluginRegistry r;
  return r;
}

void PluginRegistry::add(const std::string& type, PluginFactory f) {
  if (capture_) {
    (*capture_)[type] = std::move(f);
    return;
  }
  factories_[type] = std::move(f);
}

const PluginFactory* PluginRegistry::find(const std::string& type) const {
  auto it = factories_.find(type);
  return it == factories_.end() ? nullptr : &it->second;
}

std::vector<std::string> PluginRegistry::names() const {
  std::vector<std::string> v;
  for (const auto& [k, _] : factories_) v.push_back(k);
  return v;
}

}  // namespace plc::io
