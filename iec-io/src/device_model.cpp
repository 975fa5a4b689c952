#include "plc/io/device_model.hpp"

namespace plc::io {

RecordError DeviceModel::read_record(std::uint16_t, std::span<std::uint8_t>, std::size_t& length) {
  length = 0;
  return RecordError::InvalidIndex;
}

RecordError DeviceModel::write_record(std::uint16_t, std::span<const std::uint8_t>) {
  return RecordError::InvalidIndex;
}

RecordError DeviceModel::query_record(std::uint16_t index, std::span<const std::uint8_t> request,
                                      std::span<std::uint8_t> out, std::size_t& length) {
  if (!request.empty()) {
    length = 0;
    return RecordError::InvalidIndex;
  }
  return read_record(index, out, length);
}

DeviceModelRegistry& DeviceModelRegistry::instance() {
  static DeviceModelRegistry r;
  return r;
}

void DeviceModelRegistry::add(const std::string& name, DeviceModelFactory f) {
  if (capture_) {
    (*capture_)[name] = std::move(f);
    return;
  }
  factories_[name] = std::move(f);
}

const DeviceModelFactory* DeviceModelRegistry::find(const std::string& name) const {
  auto it = factories_.find(name);
  return it == factories_.end() ? nullptr : &it->second;
}

std::vector<std::string> DeviceModelRegistry::names() const {
  std::vector<std::string> v;
  for (const auto& [k, _] : factories_) v.push_back(k);
  return v;
}

}  // namespace plc::io
