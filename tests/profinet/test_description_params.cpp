// The device description in the cell config (description_params.hpp,
// docs/config.md "PROFINET devices"): the three forms, start-up records,
// and errors that name the key. Station-name rules: IEC 61158-6-10
// NameOfStation (DNS-style labels).
#include <gtest/gtest.h>

#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/description/description_params.hpp"

namespace pn = plc::profinet;
using plc::io::ModelParams;

namespace {

ModelParams params(std::initializer_list<std::pair<const char*, const char*>> kv) {
  ModelParams p;
  for (auto [k, v] : kv) p.set(k, v);
  return p;
}

std::string error_key(const std::string& model, const ModelParams& p) {
  try {
    pn::description_from_params(model, p);
  } catch (const plc::io::ParamError& e) {
    return e.key.empty() ? "(block)" : e.key;
  }
  return "(none)";
}

}  // namespace

TEST(DescriptionParams, BuiltinWithAddressAndStartupRecords) {
  const auto p = params({{"station_name", "e1-axis"},
                         {"ip", "10.88.0.2"},
                         {"telegram", "9"},
                         {"records.1.1", "0xB02E = 01 02; 47=A0B0C0"}});
  const auto d = pn::description_from_params("hiwin_e1", p);
  EXPECT_EQ(d.station_name, "e1-axis");
  EXPECT_EQ(pn::to_string(d.ip), "10.88.0.2");
  EXPECT_EQ(pn::to_string(d.netmask), "255.255.255.0");
  EXPECT_EQ(d.vendor_id, pn::kOurVendorId);
  ASSERT_EQ(d.io_submodule()->records.size(), 2u);
  EXPECT_EQ(d.io_submodule()->records[0], (pn::StartupRecord{0xB02E, {1, 2}}));
  EXPECT_EQ(d.io_submodule()->records[1], (pn::StartupRecord{47, {0xA0, 0xB0, 0xC0}}));
  EXPECT_EQ(d.io_submodule()->output_length, 20);  // telegram 9
  EXPECT_NO_THROW(p.reject_unknown());             // every key was read
}

TEST(DescriptionParams, GenericInlineSlots) {
  const auto p = params({{"station_name", "io-1"},
                         {"ip", "192.168.1.20"},
                         {"vendor_id", "0x002A"},
                         {"device_id", "0x0301"},
                         {"min_device_interval", "2ms"},
                         {"dap", "module=0x00010000 submodule=0x10001 interface=0x18000"},
                         {"submodule.2.1", "module=0x20 submodule=0x21 in=2"},
                         {"submodule.1.2", "module=0x10 submodule=0x12 out=4 api=0x3A00"},
                         {"submodule.1.1", "module=0x10 submodule=0x11 in=1 out=1"}});
  const auto d = pn::description_from_params("generic", p);
  EXPECT_EQ(d.vendor_id, 0x2A);
  EXPECT_EQ(d.device_id, 0x301);
  EXPECT_EQ(d.min_device_interval, std::chrono::milliseconds(2));
  ASSERT_EQ(d.modules.size(), 3u);
  EXPECT_EQ(d.modules[0].module_ident, 0x10000u);
  EXPECT_EQ(d.modules[0].submodules[1].submodule_ident, 0x18000u);
  EXPECT_EQ(d.modules[0].submodules[2].submodule_ident, 0x8001u);  // default
  EXPECT_EQ(d.modules[1].slot, 1);
  ASSERT_EQ(d.modules[1].submodules.size(), 2u);
  EXPECT_EQ(d.modules[1].submodules[0].subslot, 1);
  EXPECT_EQ(d.modules[1].submodules[1].api, 0x3A00u);
  EXPECT_EQ(d.modules[2].submodules[0].input_length, 2);
  EXPECT_EQ(d.input_size(), 3u);
  EXPECT_EQ(d.output_size(), 5u);
  EXPECT_EQ(d.io_submodule(), &d.modules[1].submodules[0]);
}

TEST(DescriptionParams, ErrorsNameTheKey) {
  const std::pair<const char*, const char*> ok[] = {{"station_name", "e1"}, {"ip", "10.0.0.2"}};
  auto with = [&](std::initializer_list<std::pair<const char*, const char*>> more) {
    ModelParams p;
    for (auto [k, v] : ok) p.set(k, v);
    for (auto [k, v] : more) p.set(k, v);
    return p;
  };
  EXPECT_EQ(error_key("hiwin_e1", params({{"ip", "10.0.0.2"}})), "station_name");
  EXPECT_EQ(error_key("hiwin_e1", params({{"station_name", "e1"}})), "ip");
  EXPECT_EQ(error_key("hiwin_e1", with({{"station_name", "E1_Axis"}})), "station_name");
  EXPECT_EQ(error_key("hiwin_e1", with({{"ip", "10.0.0"}})), "ip");
  EXPECT_EQ(error_key("hiwin_e1", with({{"telegram", "2"}})), "telegram");
  EXPECT_EQ(error_key("hiwin_e1", with({{"gsdml", "x.xml"}})), "gsdml");
  EXPECT_EQ(error_key("hiwin_e1", with({{"submodule.1.1", "module=1 submodule=1"}})),
            "submodule.1.1");
  EXPECT_EQ(error_key("hiwin_e1", with({{"records.2.1", "1=00"}})), "records.2.1");
  EXPECT_EQ(error_key("hiwin_e1", with({{"records.1.1", "1=0"}})), "records.1.1");
  EXPECT_EQ(error_key("hiwin_e1", with({{"records.1.1", "0x10000=00"}})), "records.1.1");
  EXPECT_EQ(error_key("hiwin_e1", with({{"records.1.1", "1=zz"}})), "records.1.1");
  EXPECT_EQ(error_key("hiwin_e1", with({{"records.1", "1=00"}})), "records.1");
  EXPECT_EQ(error_key("generic", with({})), "dap");
  EXPECT_EQ(error_key("generic", with({{"dap", "module=1 color=2"}})), "dap");
  EXPECT_EQ(error_key("generic", with({{"dap", "module=1"}, {"submodule.1.1", "submodule=2"}})),
            "submodule.1.1");
  EXPECT_EQ(error_key("generic", with({{"dap", "module=1"},
                                       {"submodule.1.1", "module=2 submodule=2 in=1440"}})),
            "submodule.1.1");
  EXPECT_EQ(error_key("generic", with({{"dap", "module=1"},
                                       {"submodule.1.1", "module=2 submodule=2"},
                                       {"submodule.1.2", "module=3 submodule=2"}})),
            "submodule.1.2");
  EXPECT_EQ(
      error_key("generic", with({{"dap", "module=1"}, {"submodule.0.2", "module=1 submodule=2"}})),
      "submodule.0.2");
  EXPECT_EQ(error_key("gsdml", with({})), "gsdml");
  EXPECT_EQ(error_key("gsdml", with({{"gsdml", "/nonexistent.xml"}})), "gsdml");
  EXPECT_EQ(error_key("gsdml", with({{"gsdml", "x.xml"}, {"gsdml_modules", "1"}})),
            "gsdml_modules");
  EXPECT_EQ(error_key("vf66b", with({})), "model");
}

TEST(DescriptionParams, ModelParamsOfKeepsOnlyTheModelsKeys) {
  const auto p = params({{"station_name", "e1"},
                         {"ip", "10.0.0.2"},
                         {"telegram", "3"},
                         {"records.1.1", "1=00"},
                         {"cu_per_rev", "4096"}});
  const auto m = pn::model_params_of(p);
  EXPECT_EQ(m.values().size(), 2u);
  EXPECT_TRUE(m.has("telegram"));
  EXPECT_TRUE(m.has("cu_per_rev"));
}

// IEC 61158-6-10 NameOfStation: DNS labels of a-z 0-9 '-', not n.n.n.n,
// not port-xyz / port-xyz-abcde.
TEST(DescriptionParams, StationNameRules) {
  for (const char* good :
       {"e1-axis", "plc.cell-1", "a", "port-12", "port-123x", "device-x.port-001"})
    EXPECT_EQ(pn::station_name_problem(good), "") << good;
  for (const char* bad : {"", "E1", "e1_axis", "-e1", "e1-", "a..b", ".a", "a.", "1.2.3.4",
                          "port-001", "port-001-00002", "port-001.cell", "with space"})
    EXPECT_NE(pn::station_name_problem(bad), "") << bad;
  EXPECT_NE(pn::station_name_problem(std::string(64, 'a')), "");
  EXPECT_EQ(pn::station_name_problem(std::string(63, 'a')), "");
  std::string long_name;
  for (int i = 0; i < 41; ++i) long_name += "abcde.";
  EXPECT_NE(pn::station_name_problem(long_name + "x"), "");  // 247 > 240
}
