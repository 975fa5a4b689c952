// The pieces of check_connect() (connect_check.hpp) that live in their own
// files: the expected submodules (connect_expected_check.cpp), the IOCRs'
// data and IOCS entries (connect_iocr_data_check.cpp), and the byte areas
// a device lays out for each submodule of an IOCR, which the checks and
// the warnings share.
#pragma once

#include <optional>
#include <vector>

#include "plc/profinet/description/device_description.hpp"
#include "plc/profinet/wire/blocks.hpp"

namespace plc::profinet::connect_detail {

// The expected modules grouped by API, APIs in the order they are first
// named (p-net keeps them so, across all ExpectedSubmoduleBlockReqs).
struct ExpectedApi {
  std::uint32_t api = 0;
  std::vector<const ExpectedModule*> modules;
};
std::vector<ExpectedApi> expected_apis(const ConnectRequest& req);
const ExpectedApi* find_api(const std::vector<ExpectedApi>& apis, std::uint32_t api);
const ExpectedModule* find_module(const ExpectedApi& api, std::uint16_t slot);
const ExpectedSubmodule* find_submodule(const ExpectedModule& m, std::uint16_t subslot);
const ExpectedSubmodule* find_expected(const std::vector<ExpectedApi>& apis, std::uint32_t api,
                                       std::uint16_t slot, std::uint16_t subslot);

// pf_cmdev_exp_apis_configure and what it calls.
std::optional<PnioStatus> check_expected(const ConnectRequest& req,
                                         const std::vector<ExpectedApi>& apis,
                                         const DeviceDescription& dev);

// pf_cmdev_check_iocr_apis, after the areas are laid out.
std::optional<PnioStatus> check_iocr_entries(const ConnectRequest& req,
                                             const std::vector<ExpectedApi>& apis);

// Where one submodule's data, IOPS and IOCS are in one IOCR's C_SDU (p-net
// calls it a data descriptor). A length of 0: not there.
struct Area {
  std::uint32_t start = 0, length = 0;
  [[nodiscard]] std::uint32_t end() const { return start + length; }
};
struct SubmoduleAreas {
  std::uint32_t api = 0;
  std::uint16_t slot = 0, subslot = 0;
  Area data, iops, iocs;
};
// One entry per submodule the IOCR lists, in the order p-net makes them:
// every IO data object (data, then its IOPS right after), then the IOCS
// of submodules without a data object here. Lengths from the expected
// submodule's DataDescription of the CR's direction (data, IOPS) and of
// the other direction (IOCS); entries of unknown submodules are left out
// (check_iocr_entries refuses them).
std::vector<SubmoduleAreas> lay_out(const IocrBlockReq& cr, const std::vector<ExpectedApi>& apis);
[[nodiscard]] bool overlap(const Area& a, const Area& b);

}  // namespace plc::profinet::connect_detail
