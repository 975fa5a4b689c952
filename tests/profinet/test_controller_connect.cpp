// The Connect the controller builds satisfies, by construction, every check
// p-net makes on it (fieldbus-masters.md §1 item 2, from p-net
// src/device/pf_cmdev.c), for every send clock, reduction ratio and
// data-hold factor the plugin accepts and for each description form. The
// rules are asserted here one by one from that list (not by our device's
// checker), and the encoded request must decode to the same blocks.
#include <gtest/gtest.h>

#include "plc/profinet/controller/connect_plan.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/wire/dcp.hpp"

namespace {

using namespace plc::profinet;

DeviceDescription e1(int telegram) {
  plc::io::ModelParams p;
  p.set("telegram", std::to_string(telegram));
  auto d = builtin_description("hiwin_e1", p);
  d.station_name = "conveyor";
  d.ip = *parse_ipv4("192.168.0.10");
  return d;
}
DeviceDescription nord() {
  auto d = builtin_description("nord_profisafe", {});
  d.station_name = "safety";
  d.ip = *parse_ipv4("192.168.0.11");
  return d;
}

bool power_of_two(unsigned v) { return v != 0 && (v & (v - 1)) == 0; }

// fieldbus-masters.md §1 item 2, rule by rule.
void expect_pnet_accepts(const ConnectRequest& r, const DeviceDescription& d) {
  EXPECT_EQ(r.ar.ar_type, 0x0001) << "AR type IOCARSingle";
  EXPECT_GE(r.ar.activity_timeout_factor, 1);
  EXPECT_LE(r.ar.activity_timeout_factor, 1000);
  EXPECT_TRUE(valid_station_name(r.ar.station_name)) << r.ar.station_name;
  EXPECT_FALSE(r.ar.ar_uuid.is_nil());
  ASSERT_EQ(r.iocrs.size(), 2u);
  bool input = false, output = false;
  for (const IocrBlockReq& c : r.iocrs) {
    input |= c.iocr_type == 1;
    output |= c.iocr_type == 2;
    EXPECT_EQ(c.lt, 0x8892);
    EXPECT_EQ(c.iocr_properties & 0x0F, 1u) << "RT_CLASS_1";
    EXPECT_TRUE(power_of_two(c.send_clock_factor)) << c.send_clock_factor;
    EXPECT_LE(c.send_clock_factor, 128);
    EXPECT_GE(c.reduction_ratio, 1);
    EXPECT_LE(c.reduction_ratio, 512);
    EXPECT_GE(std::int64_t{31250} * c.send_clock_factor * c.reduction_ratio,
              d.min_device_interval.count())
        << "SendClockFactor x ReductionRatio >= the device's minimum interval";
    EXPECT_GE(c.phase, 1);
    EXPECT_LE(c.phase, c.reduction_ratio);
    EXPECT_TRUE(c.frame_send_offset == 0xFFFFFFFF ||
                c.frame_send_offset < 31250u * c.send_clock_factor);
    EXPECT_GE(c.data_hold_factor, 1);
    EXPECT_LE(c.data_hold_factor, 0x1E00);
    EXPECT_GE(c.data_length, 40) << "RT_CLASS_1 data 40..1440 (padded to 40)";
    EXPECT_LE(c.data_length, 1440);
    if (c.iocr_type == 1) {
      EXPECT_GE(c.frame_id, 0xC000);
      EXPECT_LE(c.frame_id, 0xF7FF);
    }
  }
  EXPECT_TRUE(input && output);
  EXPECT_EQ(r.alarm_cr.lt, 0x8892);
  EXPECT_GE(r.alarm_cr.rta_timeout_factor, 1);
  EXPECT_LE(r.alarm_cr.rta_timeout_factor, 100);
  EXPECT_GE(r.alarm_cr.rta_retries, 3);
  EXPECT_LE(r.alarm_cr.rta_retries, 15);
  EXPECT_GE(r.alarm_cr.max_alarm_data_length, 200);
  EXPECT_LE(r.alarm_cr.max_alarm_data_length, 1432);
  // Every submodule of the description is expected, with its ident and
  // lengths.
  std::size_t expected = 0, described = 0;
  for (const auto& b : r.expected)
    for (const auto& m : b.modules) expected += m.submodules.size();
  for (const auto& m : d.modules) described += m.submodules.size();
  EXPECT_EQ(expected, described);
}

TEST(ControllerConnect, FieldbusMasters1_2_EveryPnetCheckHoldsForEverySendClockAndRatio) {
  const Mac mac{0x02, 0, 0, 0, 0, 1};
  for (const auto& desc : {e1(3), e1(9), e1(111), nord()}) {
    for (std::uint16_t scf : {8, 16, 32, 64, 128}) {
      for (std::uint16_t rr : {1, 2, 16, 512}) {
        for (std::uint16_t dhf : {1, 3, 0x1E00}) {
          ControllerConfig cfg;
          cfg.send_clock_factor = scf;
          cfg.reduction_ratio = rr;
          cfg.data_hold_factor = dhf;
          SCOPED_TRACE(desc.station_name + " scf " + std::to_string(scf) + " rr " +
                       std::to_string(rr) + " dhf " + std::to_string(dhf));
          const ConnectPlan p = plan_connect(cfg, desc, mac, make_uuid_v4(1, 2), 1, 0xC000);
          expect_pnet_accepts(p.request, desc);
          // The encoded request decodes to the same blocks.
          ConnectRequest back;
          ASSERT_TRUE(decode_connect_request(encode_connect_request(p.request), back));
          EXPECT_EQ(back.ar.ar_uuid, p.request.ar.ar_uuid);
          ASSERT_EQ(back.iocrs.size(), 2u);
          EXPECT_EQ(back.iocrs[0].data_length, p.request.iocrs[0].data_length);
          EXPECT_EQ(back.iocrs[1].reduction_ratio, p.request.iocrs[1].reduction_ratio);
        }
      }
    }
  }
}

TEST(ControllerConnect, ReductionRatioIsRaisedToTheDevicesMinimumInterval) {
  auto d = e1(111);
  d.min_device_interval = std::chrono::milliseconds(4);
  ControllerConfig cfg;  // 1 ms x 1
  const ConnectPlan p = plan_connect(cfg, d, Mac{}, make_uuid_v4(1, 2), 1, 0xC000);
  EXPECT_EQ(p.request.iocrs[0].reduction_ratio, 4);
  expect_pnet_accepts(p.request, d);
}

// The device's %I/%Q bytes are its IO submodule's data (hiwin-e1-profinet.md
// Table 3.2.1: telegram 111 = 12 words each way; nord-profisafe.md §2.1:
// the 8-byte F-PDU each way), with IOPS and IOCS beside them in the C_SDU.
TEST(ControllerConnect, UserDataIsTheIoSubmodulesDataAndFitsTheFrame) {
  const ConnectPlan p = plan_connect({}, e1(111), Mac{}, make_uuid_v4(1, 2), 1, 0xC000);
  ASSERT_EQ(p.inputs.size(), 1u);
  ASSERT_EQ(p.outputs.size(), 1u);
  EXPECT_EQ(p.inputs[0].object.length, 24);
  EXPECT_EQ(p.outputs[0].object.length, 24);
  EXPECT_EQ(p.inputs[0].object.api, 0x3A00u) << "PROFIdrive API (hiwin-e1-profinet.md §1.4)";
  const ConnectPlan n = plan_connect({}, nord(), Mac{}, make_uuid_v4(1, 2), 1, 0xC000);
  ASSERT_EQ(n.inputs.size(), 1u);
  EXPECT_EQ(n.inputs[0].object.length, 8);
  EXPECT_EQ(n.outputs[0].object.length, 8);
  EXPECT_EQ(n.inputs[0].object.slot, 1) << "SAFE submodule in slot 1 (nord-profisafe.md §3.1)";
}

TEST(ControllerConnect, ADescriptionTooLongForOneFrameIsRefusedBeforeStart) {
  auto d = e1(111);
  d.modules.back().submodules.back().input_length = 1500;
  EXPECT_THROW(plan_connect({}, d, Mac{}, make_uuid_v4(1, 2), 1, 0xC000), std::invalid_argument);
}

}  // namespace
