#include "plc/io/plugin.hpp"

#include "plc/thread_guard.hpp"

namespace plc::io {

std::string Plugin::diagnostics(std::size_t device) const {
  return std::string(to_string(const_cast<Plugin*>(this)->link(device).live_state()));
}

void Plugin::fail(std::string_view thread, std::string_view what, std::size_t devices) noexcept {
  if (failing_.exchange(true)) return;
  try {
    failure_ = std::string(thread) + " failed: " + std::string(what);
  } catch (...) {
    // No memory for the text: the state still says it.
  }
  failed_.store(true, std::memory_order_release);
  for (std::size_t i = 0; i < devices; ++i) link(i).set_state(DeviceState::Fault);
}

std::string Plugin::failure() const { return failed() ? failure_ : std::string(); }

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
