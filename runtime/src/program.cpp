#include "plc/program.hpp"

namespace plc {

ProgramRegistry& ProgramRegistry::instance() {
  static ProgramRegistry r;
  return r;
}

void ProgramRegistry::add(const std::string& type, ProgramFactory f) {
  if (capture_) {
    (*capture_)[type] = std::move(f);
    return;
  }
  factories_[type] = std::move(f);
}

const ProgramFactory* ProgramRegistry::find(const std::string& type) const {
  auto it = factories_.find(type);
  return it == factories_.end() ? nullptr : &it->second;
}

std::vector<std::string> ProgramRegistry::names() const {
  std::vector<std::string> v;
  for (const auto& [k, _] : factories_) v.push_back(k);
  return v;
}

}  // namespace plc
