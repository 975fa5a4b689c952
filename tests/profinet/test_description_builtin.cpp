// The built-in descriptions of our two devices: equal to the ones loaded
// from our GSDML files (iec-io/profinet/gsdml/), and their IO submodule's
// lengths equal to the device models' input_size()/output_size() for the
// same params, so the FBs see the same process image over PROFINET as over
// the sim plugin.
#include <gtest/gtest.h>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/description/gsdml.hpp"
#include "plc/sim/nord_profisafe_model.hpp"
#include "plc_test_paths.hpp"

namespace pn = plc::profinet;

namespace {

const std::string kE1Gsdml =
    plctest::source_path("iec-io/profinet/gsdml/GSDML-V2.4-softplc-HIWIN-E1-SIM-20261130.xml");
const std::string kNordGsdml =
    plctest::source_path("iec-io/profinet/gsdml/GSDML-V2.4-softplc-NORD-TU4-PNS-SIM-20261130.xml");

plc::io::ModelParams telegram(int t) {
  plc::io::ModelParams p;
  p.set("telegram", std::to_string(t));
  return p;
}

}  // namespace

// hiwin-e1-profinet.md §3.1 Table 3.2.1: received (PLC -> drive) and sent
// (drive -> PLC) words per telegram; §1.4: the drive object is in API 0x3A00.
TEST(DescriptionBuiltin, HiwinE1TelegramSizesOfTable321InApi3A00) {
  struct Row {
    int telegram, out_words, in_words;
  };
  for (const Row r : {Row{3, 5, 9}, Row{9, 10, 5}, Row{111, 12, 12}}) {
    SCOPED_TRACE(r.telegram);
    const auto d = pn::builtin_description("hiwin_e1", telegram(r.telegram));
    const auto* io = d.io_submodule();
    ASSERT_NE(io, nullptr);
    EXPECT_EQ(io->api, pn::kApiProfidrive);
    EXPECT_EQ(io->output_length, 2 * r.out_words);
    EXPECT_EQ(io->input_length, 2 * r.in_words);
    EXPECT_EQ(d.module_of(io)->slot, 1);
    EXPECT_EQ(io->subslot, 1);
  }
}

TEST(DescriptionBuiltin, HiwinE1LengthsEqualTheDeviceModels) {
  for (int t : {3, 9, 111}) {
    SCOPED_TRACE(t);
    const auto d = pn::builtin_description("hiwin_e1", telegram(t));
    plc::sim::HiwinE1Model model(telegram(t));
    EXPECT_EQ(d.input_size(), model.input_size());
    EXPECT_EQ(d.output_size(), model.output_size());
    EXPECT_EQ(d.io_submodule()->input_length, model.input_size());
  }
}

// nord-profisafe.md §2.1, §3.1: slot 1 SAFE, 8-byte F-PDU each way.
TEST(DescriptionBuiltin, NordSafeSubmoduleInSlot1EqualsTheDeviceModel) {
  const plc::io::ModelParams none;
  const auto d = pn::builtin_description("nord_profisafe", none);
  plc::sim::NordProfisafeModel model(none);
  const auto* io = d.io_submodule();
  ASSERT_NE(io, nullptr);
  EXPECT_EQ(d.module_of(io)->slot, 1);
  EXPECT_EQ(io->input_length, model.input_size());
  EXPECT_EQ(io->output_length, model.output_size());
  EXPECT_EQ(io->input_length, 8);
  // The F-host block writes the F-parameter record itself (§2.2).
  EXPECT_TRUE(io->records.empty());
}

TEST(DescriptionBuiltin, HiwinE1EqualsOurGsdmlByModuleIdAndByName) {
  for (int t : {3, 9, 111}) {
    SCOPED_TRACE(t);
    const auto builtin = pn::builtin_description("hiwin_e1", telegram(t));
    pn::GsdmlSelection by_id{"DAP_E1", {{1, "ID_Mod_Tel" + std::to_string(t)}}};
    EXPECT_EQ(pn::load_gsdml(kE1Gsdml, by_id), builtin);
    const std::string name =
        t == 111 ? "HIWIN telegram 111" : "Standard telegram " + std::to_string(t);
    pn::GsdmlSelection by_name{"", {{1, name}}};
    EXPECT_EQ(pn::load_gsdml(kE1Gsdml, by_name), builtin);
  }
}

TEST(DescriptionBuiltin, NordEqualsOurGsdml) {
  const auto builtin = pn::builtin_description("nord_profisafe", {});
  EXPECT_EQ(pn::load_gsdml(kNordGsdml, {"", {{1, "SAFE"}}}), builtin);
}

TEST(DescriptionBuiltin, DapHasTheSubslotsAConnectExpects) {
  for (const char* model : {"hiwin_e1", "nord_profisafe"}) {
    auto d = pn::builtin_description(model, {});
    d.station_name = "dev-1";
    EXPECT_EQ(pn::check(d), "") << model;
    ASSERT_EQ(d.modules[0].slot, 0);
    ASSERT_EQ(d.modules[0].submodules.size(), 3u);
    EXPECT_EQ(d.modules[0].submodules[0].subslot, pn::kDapSubslot);
    EXPECT_EQ(d.modules[0].submodules[1].subslot, pn::kInterfaceSubslot);
    EXPECT_EQ(d.modules[0].submodules[2].subslot, pn::kPortSubslot);
  }
}

TEST(DescriptionBuiltin, BadTelegramAndUnknownModelNameTheKey) {
  try {
    pn::builtin_description("hiwin_e1", telegram(1));
    FAIL();
  } catch (const plc::io::ParamError& e) {
    EXPECT_EQ(e.key, "telegram");
  }
  try {
    pn::builtin_description("vf66b", {});
    FAIL();
  } catch (const plc::io::ParamError& e) {
    EXPECT_EQ(e.key, "model");
  }
}
