#include "plc/profinet/description/device_description.hpp"

#include <cctype>
#include <cstdio>

namespace plc::profinet {

std::size_t DeviceDescription::input_size() const {
  std::size_t n = 0;
  for (const auto& m : modules)
    for (const auto& s : m.submodules) n += s.input_length;
  return n;
}

std::size_t DeviceDescription::output_size() const {
  std::size_t n = 0;
  for (const auto& m : modules)
    for (const auto& s : m.submodules) n += s.output_length;
  return n;
}

const SubmoduleDescription* DeviceDescription::io_submodule() const {
  const SubmoduleDescription* first_outside_dap = nullptr;
  for (const auto& m : modules) {
    if (m.slot == 0) continue;
    for (const auto& s : m.submodules) {
      if (s.input_length + s.output_length > 0) return &s;
      if (!first_outside_dap) first_outside_dap = &s;
    }
  }
  if (first_outside_dap) return first_outside_dap;
  if (!modules.empty() && !modules.front().submodules.empty())
    return &modules.front().submodules.front();
  return nullptr;
}

const ModuleDescription* DeviceDescription::module_of(const SubmoduleDescription* s) const {
  for (const auto& m : modules)
    for (const auto& x : m.submodules)
      if (&x == s) return &m;
  return nullptr;
}

namespace {

bool all_digits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

// "port-xyz" or "port-xyz-abcde" (x..e digits) as the whole name or its
// first label: reserved for port names (IEC 61158-6-10 NameOfStation).
bool port_name_form(const std::string& label) {
  if (label.size() < 8 || label.compare(0, 5, "port-") != 0) return false;
  if (!all_digits(label.substr(5, 3))) return false;
  if (label.size() == 8) return true;
  return label.size() == 14 && label[8] == '-' && all_digits(label.substr(9, 5));
}

}  // namespace

std::string station_name_problem(const std::string& name) {
  if (name.empty()) return "the station name is empty";
  if (name.size() > 240) return "the station name is longer than 240 characters";
  std::size_t start = 0;
  int labels = 0;
  bool all_numeric = true;
  std::string first;
  while (start <= name.size()) {
    const auto dot = name.find('.', start);
    const std::string label =
        name.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (label.empty()) return "the station name has an empty label (two dots, or a dot at an end)";
    if (label.size() > 63) return "a label of the station name is longer than 63 characters";
    for (char c : label)
      if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-'))
        return std::string("the station name may hold only a-z, 0-9, '-' and '.', not '") + c + "'";
    if (label.front() == '-' || label.back() == '-')
      return "a label of the station name starts or ends with '-'";
    if (!all_digits(label)) all_numeric = false;
    if (labels == 0) first = label;
    ++labels;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (labels == 4 && all_numeric) return "the station name has the form of an IP address";
  if (port_name_form(first)) return "the station name starts with a port name (port-xyz)";
  return "";
}

std::string check(const DeviceDescription& d) {
  if (auto why = station_name_problem(d.station_name); !why.empty()) return why;
  if (d.modules.empty() || d.modules.front().slot != 0)
    return "the description has no DAP (module in slot 0)";
  const auto& dap = d.modules.front();
  for (std::uint16_t sub : {kDapSubslot, kInterfaceSubslot, kPortSubslot}) {
    bool found = false;
    for (const auto& s : dap.submodules) found = found || s.subslot == sub;
    if (!found) {
      char b[8];
      std::snprintf(b, sizeof b, "0x%04X", sub);
      return std::string("the DAP has no submodule in subslot ") + b;
    }
  }
  // One RT_CLASS_1 frame carries at most 1440 bytes of IO data objects:
  // each submodule's data + IOPS in one direction, and an IOCS for each of
  // the other direction's (fieldbus-masters.md §1 item 2).
  std::size_t in_frame = 0, out_frame = 0;
  for (std::size_t i = 0; i < d.modules.size(); ++i) {
    const auto& m = d.modules[i];
    if (i > 0 && m.slot <= d.modules[i - 1].slot)
      return "slot " + std::to_string(m.slot) + " is not in ascending order or given twice";
    if (m.submodules.empty()) return "slot " + std::to_string(m.slot) + " has no submodule";
    for (std::size_t j = 0; j < m.submodules.size(); ++j) {
      const auto& s = m.submodules[j];
      if (j > 0 && s.subslot <= m.submodules[j - 1].subslot)
        return "slot " + std::to_string(m.slot) + ": subslot " + std::to_string(s.subslot) +
               " is not in ascending order or given twice";
      // Input CR: data + IOPS of each submodule with inputs or no data
      // (those count as inputs), the IOCS of each with outputs; the output
      // CR the other way round.
      const bool input_side = s.input_length > 0 || s.output_length == 0;
      const bool output_side = s.output_length > 0;
      in_frame += (input_side ? s.input_length + 1u : 0u) + (output_side ? 1u : 0u);
      out_frame += (output_side ? s.output_length + 1u : 0u) + (input_side ? 1u : 0u);
    }
  }
  if (in_frame > 1440 || out_frame > 1440)
    return "the IO data (with IOPS/IOCS) do not fit one RT_CLASS_1 frame of 1440 bytes";
  return "";
}

}  // namespace plc::profinet
