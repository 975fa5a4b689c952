// The ExpectedSubmoduleBlockReq checks of check_connect(), after p-net's
// pf_cmdev_exp_apis_configure / _exp_modules_configure /
// _exp_submodule_configure (ErrorCode1 0x03). Our device does not plug
// modules on request as a p-net application may: a slot or subslot it does
// not have is refused (0x06 / 0x0A), as p-net refuses one its application
// did not plug.
#include <algorithm>

#include "connect_parts.hpp"
#include "plc/profinet/device/connect_check.hpp"

namespace plc::profinet::connect_detail {

namespace {

using connect_error::kExpectedBlock;

std::optional<PnioStatus> fail(std::uint8_t code2) {
  return connect_refusal(kExpectedBlock, code2);
}

const ModuleDescription* device_module(const DeviceDescription& dev, std::uint16_t slot) {
  for (const auto& m : dev.modules)
    if (m.slot == slot) return &m;
  return nullptr;
}
bool device_has_subslot(const ModuleDescription& m, std::uint16_t subslot) {
  return std::any_of(m.submodules.begin(), m.submodules.end(),
                     [&](const auto& s) { return s.subslot == subslot; });
}

bool listed_in_some_iocr(const ConnectRequest& req, std::uint32_t api, std::uint16_t slot,
                         std::uint16_t subslot) {
  auto here = [&](const IocrEntry& e) { return e.slot == slot && e.subslot == subslot; };
  for (const auto& c : req.iocrs)
    for (const auto& a : c.apis)
      if (a.api == api && (std::any_of(a.data_objects.begin(), a.data_objects.end(), here) ||
                           std::any_of(a.iocs.begin(), a.iocs.end(), here)))
        return true;
  return false;
}

// The DataDescriptions must fit the Type: one input description for NO_IO
// and input submodules, one output description for output submodules, one
// of each for IO submodules (code 0x0C).
bool descriptions_fit_type(std::uint16_t type, const std::vector<DataDescription>& d) {
  auto dir = [&](std::size_t i, std::uint16_t want) { return d[i].direction == want; };
  switch (type) {
    case submodule::kTypeNoIo:
    case submodule::kTypeInput:
      return d.size() == 1 && dir(0, submodule::kDataInput);
    case submodule::kTypeOutput:
      return d.size() == 1 && dir(0, submodule::kDataOutput);
    default:
      return d.size() == 2 && (dir(0, submodule::kDataInput) || dir(1, submodule::kDataInput)) &&
             (dir(0, submodule::kDataOutput) || dir(1, submodule::kDataOutput));
  }
}

std::optional<PnioStatus> check_submodule(const ConnectRequest& req, std::uint32_t api,
                                          const ExpectedModule& m, std::size_t k,
                                          const ModuleDescription& real) {
  const ExpectedSubmodule& s = m.submodules[k];
  for (std::size_t l = 0; l < k; ++l)
    if (m.submodules[l].subslot == s.subslot) return fail(10);
  if (!listed_in_some_iocr(req, api, m.slot, s.subslot)) return fail(10);
  if (s.subslot > 0x9FFF) return fail(10);
  if (!device_has_subslot(real, s.subslot)) return fail(10);
  if (s.subslot >= kInterfaceSubslot && api != 0) return fail(10);

  const std::uint16_t type = s.type();
  const auto descriptions = s.wire_descriptions();
  const bool input_type = type == submodule::kTypeInput || type == submodule::kTypeInputOutput;
  const bool output_type = type == submodule::kTypeOutput || type == submodule::kTypeInputOutput;
  if (!descriptions_fit_type(type, descriptions)) return fail(12);
  if (type == submodule::kTypeOutput && (s.properties & submodule::kSharedInput)) return fail(12);
  // p-net allows ReduceInput/OutputSubmoduleDataLength only on submodules
  // without data in that direction, and DiscardIOXS only on IO submodules.
  if ((s.properties & submodule::kReduceInputLength) && input_type) return fail(12);
  if ((s.properties & submodule::kReduceOutputLength) && output_type) return fail(12);
  if ((s.properties & submodule::kDiscardIoxs) && type != submodule::kTypeInputOutput)
    return fail(12);
  for (const DataDescription& d : descriptions) {
    // 0x0D cannot fail once 0x0C passed; kept so that the codes stay p-net's.
    if (d.direction != submodule::kDataInput && d.direction != submodule::kDataOutput)
      return fail(13);
    if (d.direction == submodule::kDataInput && type == submodule::kTypeOutput) return fail(13);
    if (d.direction == submodule::kDataOutput && !output_type) return fail(13);
    if (d.length > 1439 || (type == submodule::kTypeNoIo && d.length != 0)) return fail(14);
    if (d.length_iops != 1) return fail(15);
    if (d.length_iocs != 1) return fail(16);
  }
  return std::nullopt;
}

}  // namespace

std::vector<ExpectedApi> expected_apis(const ConnectRequest& req) {
  std::vector<ExpectedApi> out;
  for (const auto& b : req.expected)
    for (const auto& m : b.modules) {
      auto it = std::find_if(out.begin(), out.end(),
                             [&](const ExpectedApi& a) { return a.api == m.api; });
      if (it == out.end()) it = out.insert(out.end(), ExpectedApi{m.api, {}});
      it->modules.push_back(&m);
    }
  return out;
}

const ExpectedApi* find_api(const std::vector<ExpectedApi>& apis, std::uint32_t api) {
  for (const auto& a : apis)
    if (a.api == api) return &a;
  return nullptr;
}
const ExpectedModule* find_module(const ExpectedApi& api, std::uint16_t slot) {
  for (const ExpectedModule* m : api.modules)
    if (m->slot == slot) return m;
  return nullptr;
}
const ExpectedSubmodule* find_submodule(const ExpectedModule& m, std::uint16_t subslot) {
  for (const auto& s : m.submodules)
    if (s.subslot == subslot) return &s;
  return nullptr;
}
const ExpectedSubmodule* find_expected(const std::vector<ExpectedApi>& apis, std::uint32_t api,
                                       std::uint16_t slot, std::uint16_t subslot) {
  const ExpectedApi* a = find_api(apis, api);
  const ExpectedModule* m = a ? find_module(*a, slot) : nullptr;
  return m ? find_submodule(*m, subslot) : nullptr;
}

std::optional<PnioStatus> check_expected(const ConnectRequest& req,
                                         const std::vector<ExpectedApi>& apis,
                                         const DeviceDescription& dev) {
  if (apis.empty()) return fail(4);
  for (const ExpectedApi& a : apis) {
    for (std::size_t i = 0; i < a.modules.size(); ++i) {
      const ExpectedModule& m = *a.modules[i];
      for (std::size_t j = 0; j < i; ++j)
        if (a.modules[j]->slot == m.slot) return fail(6);
      if (m.slot > 0x7FFF) return fail(6);
      const ModuleDescription* real = device_module(dev, m.slot);
      if (!real) return fail(6);
      if (m.module_ident == 0) return fail(7);
      if (m.submodules.empty()) return fail(9);
      for (std::size_t k = 0; k < m.submodules.size(); ++k)
        if (auto e = check_submodule(req, a.api, m, k, *real)) return e;
    }
  }
  return std::nullopt;
}

}  // namespace plc::profinet::connect_detail
