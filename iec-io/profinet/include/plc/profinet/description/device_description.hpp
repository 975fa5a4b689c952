// What the IO controller and the device simulator both need to know about a
// PROFINET device to set up an AR with it: identity, address, and the
// expected submodules (the ExpectedSubmoduleBlockReq of a Connect, and from
// it the IO data layout of the cyclic frames), with their start-up records.
//
// Filled from the cell config (description_params.hpp), a GSDML file
// (gsdml.hpp) or a built-in description (builtin_descriptions.hpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "plc/profinet/link/address.hpp"

namespace plc::profinet {

// Subslots of the DAP (slot 0) every device has (IEC 61158-6-10: the DAP
// submodule, the interface and its first port).
inline constexpr std::uint16_t kDapSubslot = 0x0001;
inline constexpr std::uint16_t kInterfaceSubslot = 0x8000;
inline constexpr std::uint16_t kPortSubslot = 0x8001;
// The PROFIdrive application process (hiwin-e1-profinet.md §1.4).
inline constexpr std::uint32_t kApiProfidrive = 0x3A00;

// A parameter record the controller writes at start-up (one MultipleWrite,
// before PrmEnd), in this order.
struct StartupRecord {
  std::uint16_t index = 0;
  std::vector<std::uint8_t> data;
  friend bool operator==(const StartupRecord&, const StartupRecord&) = default;
};

struct SubmoduleDescription {
  std::uint16_t subslot = 1;
  std::uint32_t api = 0;
  std::uint32_t submodule_ident = 0;
  std::uint16_t input_length = 0;   // IO data bytes device -> controller (no IOPS)
  std::uint16_t output_length = 0;  // IO data bytes controller -> device (no IOPS)
  std::vector<StartupRecord> records;
  friend bool operator==(const SubmoduleDescription&, const SubmoduleDescription&) = default;
};

struct ModuleDescription {
  std::uint16_t slot = 0;
  std::uint32_t module_ident = 0;
  std::vector<SubmoduleDescription> submodules;  // ascending subslot
  friend bool operator==(const ModuleDescription&, const ModuleDescription&) = default;
};

struct DeviceDescription {
  std::string station_name;  // NameOfStation (DCP)
  Ipv4 ip;
  Ipv4 netmask{0xFFFFFF00};
  Ipv4 gateway;  // 0.0.0.0 = none
  std::uint16_t vendor_id = 0;
  std::uint16_t device_id = 0;
  std::uint16_t instance = 1;  // the device's RPC object instance
  // Ascending slot; modules[0] is the DAP in slot 0 (its module ident is the
  // DAP ident) with submodules 0x0001, 0x8000 and 0x8001.
  std::vector<ModuleDescription> modules;
  // Smallest SendClockFactor x ReductionRatio the device accepts
  // (GSDML MinDeviceInterval x 31.25 us).
  std::chrono::nanoseconds min_device_interval{std::chrono::milliseconds(1)};
  friend bool operator==(const DeviceDescription&, const DeviceDescription&) = default;

  // Sums of the input/output lengths over all submodules: the bytes the
  // device occupies in %I / %Q (submodules in slot, subslot order).
  [[nodiscard]] std::size_t input_size() const;
  [[nodiscard]] std::size_t output_size() const;
  // The submodule that carries the device's IO data and serves its records
  // (RecordRequest from the FBs): the first one outside the DAP with IO
  // data, else the first outside the DAP, else the DAP submodule. nullptr
  // only for a description without modules.
  [[nodiscard]] const SubmoduleDescription* io_submodule() const;
  [[nodiscard]] const ModuleDescription* module_of(const SubmoduleDescription* s) const;
};

// Consistency a Connect needs: a DAP in slot 0 with 0x0001/0x8000/0x8001,
// slots and subslots ascending and unique, lengths within one RT_CLASS_1
// frame (1440 bytes incl. one IOPS and one IOCS per submodule), a valid
// station name. Returns "" or the first problem, worded for a config error.
std::string check(const DeviceDescription& d);

// IEC 61158-6-10 NameOfStation rules: 1..240 characters, labels of 1..63
// of a-z, 0-9, '-' separated by '.', no label starting or ending with '-',
// not of the form n.n.n.n, not starting with "port-xyz" / "port-xyz-abcde"
// (x, y, z, a..e digits). Returns "" or why not.
std::string station_name_problem(const std::string& name);

}  // namespace plc::profinet
