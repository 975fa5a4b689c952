#include "plc/profinet/description/builtin_descriptions.hpp"

namespace plc::profinet {

namespace {

using std::chrono::microseconds;

// The DAP of one of our devices: module ident BASE, submodule BASE+1,
// interface BASE+0x8000, port BASE+0x8001 (README, "Ident numbers").
ModuleDescription dap(std::uint32_t base) {
  ModuleDescription m;
  m.slot = 0;
  m.module_ident = base;
  m.submodules = {{kDapSubslot, 0, base + 0x0001, 0, 0, {}},
                  {kInterfaceSubslot, 0, base + 0x8000, 0, 0, {}},
                  {kPortSubslot, 0, base + 0x8001, 0, 0, {}}};
  return m;
}

// hiwin-e1-profinet.md §3.1 Table 3.2.1: words PLC -> drive / drive -> PLC.
// (fblocks/drive/telegrams.hpp has the same sizes; a test checks both
// against the device model, which uses that header.)
struct TelegramWords {
  unsigned telegram, out_words, in_words;
};
constexpr TelegramWords kTelegrams[] = {{3, 5, 9}, {9, 10, 5}, {111, 12, 12}};

DeviceDescription hiwin_e1(const io::ModelParams& p) {
  const auto tg = static_cast<unsigned>(p.get_int("telegram", 111, 0, 65535));
  const TelegramWords* t = nullptr;
  for (const auto& x : kTelegrams)
    if (x.telegram == tg) t = &x;
  if (!t)
    throw io::ParamError("telegram",
                         "telegram must be 3, 9 or 111 (hiwin-e1-profinet.md §1.2), "
                         "got " +
                             std::to_string(tg));
  DeviceDescription d;
  d.vendor_id = kOurVendorId;
  d.device_id = kHiwinE1DeviceId;
  // RT send clock down to 500 us (§1.2 Table 2.2.1).
  d.min_device_interval = microseconds(500);
  d.modules.push_back(dap(0x0E010000));
  // The drive object in API 0x3A00 (§1.4); module = submodule ident
  // 0x0E01_0000 + the telegram number.
  const std::uint32_t ident = 0x0E010000u + tg;
  ModuleDescription m;
  m.slot = 1;
  m.module_ident = ident;
  m.submodules = {{1,
                   kApiProfidrive,
                   ident,
                   static_cast<std::uint16_t>(2 * t->in_words),
                   static_cast<std::uint16_t>(2 * t->out_words),
                   {}}};
  d.modules.push_back(std::move(m));
  return d;
}

DeviceDescription nord_profisafe(const io::ModelParams&) {
  DeviceDescription d;
  d.vendor_id = kOurVendorId;
  d.device_id = kNordProfisafeDeviceId;
  // Smallest send interval 1 ms (nord-profisafe.md §1.3).
  d.min_device_interval = microseconds(1000);
  d.modules.push_back(dap(0x02800000));
  // Slot 1 "SAFE" (P180 code 16 = 0x10, §3.1): the 8-byte F-PDU each way
  // (§2.1). No start-up record: the F-host block (fblocks/safety f_module)
  // writes the F-parameters (record 128) itself, as it does over the sim
  // plugin (§2.2: "the F-host sends the F-parameters").
  ModuleDescription m;
  m.slot = 1;
  m.module_ident = 0x02800010;
  m.submodules = {{1, 0, 0x02800010, 8, 8, {}}};
  d.modules.push_back(std::move(m));
  return d;
}

}  // namespace

std::vector<std::string> builtin_models() { return {"hiwin_e1", "nord_profisafe"}; }

bool is_builtin_model(const std::string& model) {
  return model == "hiwin_e1" || model == "nord_profisafe";
}

DeviceDescription builtin_description(const std::string& model, const io::ModelParams& params) {
  if (model == "hiwin_e1") return hiwin_e1(params);
  if (model == "nord_profisafe") return nord_profisafe(params);
  throw io::ParamError("model", "no built-in PROFINET description for model '" + model +
                                    "' (built in: hiwin_e1, nord_profisafe; else gsdml or "
                                    "generic)");
}

}  // namespace plc::profinet
