// The simulated E1 driven with raw telegrams: the standard STW1 patterns of
// spec §5 and the ZSW1 values it derives, faults, sign-of-life, the PNU
// dictionary behind the parameter channel (§6.4/§6.5), 3200h/3215h and the
// absolute encoder across a power cycle.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/fb/drive/scaling.hpp"
#include "plc/fb/drive/sign_of_life.hpp"
#include "plc/fb/drive/telegrams.hpp"
#include "plc/io/model_params.hpp"

namespace plc::sim {

using namespace plc::drive;
using namespace std::chrono_literals;
using State = HiwinE1Model::State;

struct RawDrive {
  explicit RawDrive(TelegramType t, HiwinE1Config c = {}) : m((c.telegram = t, c)), tg(t) {
    out.resize(m.output_size());
    in.resize(m.input_size());
  }
  // One drive cycle with control word `stw1` (sign-of-life kept running).
  void cycle(std::uint16_t stw1, int n = 1) {
    for (int i = 0; i < n; ++i) {
      sol = next_sign_of_life(sol);
      io::store_be<std::uint16_t>(out, 0, stw1);
      const std::size_t stw2 = tg == TelegramType::Standard3   ? Telegram3Out::kStw2
                               : tg == TelegramType::Standard9 ? Telegram9Out::kStw2
                                                               : Telegram111Out::kStw2;
      io::store_be<std::uint16_t>(out, stw2, static_cast<std::uint16_t>(sol << 12));
      now += 1ms;
      m.step(now, 1ms, out, in);
    }
  }
  std::uint16_t zsw1() const { return io::load_be<std::uint16_t>(in, 0); }
  // Parameter channel round trip: write request, read response.
  ParamResponse param(const ParamRequest& r, std::uint16_t index = kParamRecordIndex) {
    std::array<std::uint8_t, 240> b{};
    const std::size_t n = r.encode(b);
    EXPECT_EQ(m.write_record(index, {b.data(), n}), io::RecordError::None);
    std::size_t len = 0;
    EXPECT_EQ(m.read_record(index, b, len), io::RecordError::None);
    ParamResponse resp;
    EXPECT_TRUE(decode_response({b.data(), len}, resp));
    return resp;
  }
  std::uint16_t param_error(ParamRequest r) {
    const auto resp = param(r);
    return resp.negative() ? resp.error_no : 0xFFFF;
  }
  HiwinE1Model m;
  TelegramType tg;
  std::vector<std::uint8_t> out, in;
  std::uint8_t sol = 0;
  TIME now{};
};

ParamRequest rd(std::uint16_t pnu, std::uint16_t sub = 0, std::uint8_t n = 0) {
  ParamRequest r;
  r.request_id = 1;
  r.pnu = pnu;
  r.subindex = sub;
  r.num_elements = n;
  return r;
}
ParamRequest wr(std::uint16_t pnu, std::uint8_t fmt, std::uint32_t raw, std::uint16_t sub = 0) {
  ParamRequest r;
  r.request_id = 2;
  r.pnu = pnu;
  r.subindex = sub;
  r.format = fmt;
  r.num_values = 1;
  r.values[0] = raw;
  return r;
}

// Spec §5 "Example ZSW1 values" for telegram 3 (ZSW1.9 = 1, no warning).
TEST(Spec5, Telegram3PatternsGiveDerivedZsw1) {
  RawDrive d(TelegramType::Standard3);
  d.cycle(0x0000);
  EXPECT_EQ(d.zsw1(), 0x0240);  // S1 with STW1 = 0
  d.cycle(0x047E);
  EXPECT_EQ(d.m.state(), State::S2);
  EXPECT_EQ(d.zsw1(), 0x0231);
  d.cycle(0x0477);  // ON without enable operation
  EXPECT_EQ(d.m.state(), State::S3);
  EXPECT_EQ(d.zsw1(), 0x0233);
  d.cycle(0x047F);
  EXPECT_EQ(d.m.state(), State::S4);
  EXPECT_EQ(d.zsw1() & ~0x0500, 0x0237);  // + 0x0100 in tolerance, 0x0400 speed reached
  EXPECT_EQ(d.zsw1(), 0x0737);            // at standstill with NSOLL_B = 0 both are set
  d.cycle(0x047E);                        // OFF1 -> S5 -> S2
  EXPECT_EQ(d.zsw1() & 0x0007, 0x0001);
  d.cycle(0x047E, 5);
  EXPECT_EQ(d.m.state(), State::S2);
  d.cycle(0x047F);
  EXPECT_EQ(d.m.state(), State::S4);  // S2 -> S4 in one step with STW1.3 = 1
}

// Spec §5 typical patterns for telegram 3: OFF2 0x047D, OFF3 0x047B,
// fault acknowledge 0x04FE (then cleared).
TEST(Spec5, Telegram3StopAndAckPatterns) {
  RawDrive d(TelegramType::Standard3);
  d.cycle(0x047E);
  d.cycle(0x047F);
  d.cycle(0x047D);
  EXPECT_EQ(d.m.state(), State::S1);
  EXPECT_EQ(d.zsw1() & 0x007F, 0x0060);  // switch-on inhibited, OFF2 active (b4 = 0)
  d.cycle(0x047E);
  d.cycle(0x047F);
  d.cycle(0x047B);
  EXPECT_EQ(d.zsw1() & 0x0027, 0x0000);  // OFF3: b5 = 0, b0..b2 = 0
  d.cycle(0x047B, 5);
  EXPECT_EQ(d.m.state(), State::S1);
  d.cycle(0x047E);
  d.cycle(0x047F);
  d.m.trip_alarm(0x400);  // AL.400 overvoltage
  d.cycle(0x047F);
  EXPECT_EQ(d.zsw1() & 0x000F, 0x0008);
  d.cycle(0x04FE);  // rising edge of bit 7
  EXPECT_EQ(d.m.state(), State::S1);
  EXPECT_EQ(d.zsw1(), 0x0270);  // S1 with STW1.1 = STW1.2 = 1: b4, b5, b6, b9
  d.cycle(0x047E);
  EXPECT_EQ(d.zsw1(), 0x0231);
}

// Table 3.7.1 / 3.8.1: parking sensor and sensor-error acknowledge (telegram 3).
TEST(Table3_8_1, EncoderParkingAndAck) {
  RawDrive d(TelegramType::Standard3);
  io::store_be<std::uint16_t>(d.out, Telegram3Out::kG1Stw, 0x4000);
  d.cycle(0x047E);
  auto g = G1Zsw::from(io::load_be<std::uint16_t>(d.in, Telegram3In::kG1Zsw));
  EXPECT_TRUE(g.parking_active);
  io::store_be<std::uint16_t>(d.out, Telegram3Out::kG1Stw, 0x8000);
  d.cycle(0x047E);
  g = G1Zsw::from(io::load_be<std::uint16_t>(d.in, Telegram3In::kG1Zsw));
  EXPECT_TRUE(g.error_ack_in_process);
  EXPECT_FALSE(g.parking_active);
  d.cycle(0x047E);
  g = G1Zsw::from(io::load_be<std::uint16_t>(d.in, Telegram3In::kG1Zsw));
  EXPECT_FALSE(g.error_ack_in_process);
}

TEST(Spec5, OffPatternsTelegram111) {
  RawDrive d(TelegramType::Hiwin111);
  d.cycle(0x043E);
  EXPECT_EQ(d.m.state(), State::S2);
  d.cycle(0x043F);
  EXPECT_EQ(d.m.state(), State::S4);
  EXPECT_EQ(d.zsw1() & 0x007F, 0x0037);
  d.cycle(0x043D);  // OFF2: clear bit 1 -> S1 at once, ZSW1.4 = 0
  EXPECT_EQ(d.m.state(), State::S1);
  EXPECT_EQ(d.zsw1() & 0x0070, 0x0060);  // bit 4 = 0 (OFF2 active), 5 = 1, 6 = 1
  d.cycle(0x043E, 2);
  d.cycle(0x043F);
  EXPECT_EQ(d.m.state(), State::S4);
  d.cycle(0x043B);                  // OFF3: clear bit 2 -> S5 (quick stop) -> S1
  EXPECT_EQ(d.zsw1() & 0x0020, 0);  // ZSW1.5 = 0 while OFF3 is active
  d.cycle(0x043B, 20);
  EXPECT_EQ(d.m.state(), State::S1);
  d.cycle(0x043F, 3);
  EXPECT_EQ(d.m.state(), State::S1);  // stays S1 while STW1.0 = 1
  d.cycle(0x043E);
  EXPECT_EQ(d.m.state(), State::S2);
}

TEST(Spec5, ControlByPlcZeroKeepsLastValidControlWord) {
  RawDrive d(TelegramType::Hiwin111);
  d.cycle(0x043E);
  d.cycle(0x043F);
  EXPECT_EQ(d.m.state(), State::S4);
  d.cycle(0x0000, 5);  // STW1.10 = 0: ignored
  EXPECT_EQ(d.m.state(), State::S4);
  EXPECT_TRUE(d.zsw1() & Zsw1Pos::kControlRequested);
}

TEST(Spec8, FaultCodeAndAcknowledgeOnRisingEdge) {
  RawDrive d(TelegramType::Hiwin111);
  d.cycle(0x043E);
  d.cycle(0x043F);
  ASSERT_TRUE(d.m.trip_alarm(0x710, true));  // AL.710 overload, cause persists
  d.cycle(0x043F);
  EXPECT_EQ(d.zsw1() & 0x000F, 0x0008);  // b3 = 1, b0..b2 = 0
  EXPECT_EQ(io::load_be<std::uint16_t>(d.in, Telegram111In::kFaultCode), 0x0710);
  d.cycle(0x04BF);  // ack while the cause is present: no effect
  d.cycle(0x043F);
  EXPECT_EQ(d.m.state(), State::Fault);
  d.m.clear_alarm_cause();
  d.cycle(0x04BF);  // holding bit 7 from before would not work: this is a new edge
  EXPECT_EQ(d.m.state(), State::S1);
  EXPECT_EQ(io::load_be<std::uint16_t>(d.in, Telegram111In::kFaultCode), 0);
  // PNU 945/947/944/952: fault buffer
  EXPECT_EQ(d.param(rd(945)).values[0], 0x0710u);
  EXPECT_EQ(d.param(rd(947)).values[0], 24u);
  EXPECT_EQ(d.param(rd(952)).values[0], 1u);
  EXPECT_EQ(d.param(rd(950, 0, 2)).values[1], 8u);
  EXPECT_EQ(d.param_error(wr(952, 0x06, 1)), 0x06);  // may only be reset
  EXPECT_EQ(d.param_error(wr(952, 0x06, 0)), 0xFFFF);
  EXPECT_EQ(d.param(rd(945)).values[0], 0u);
  EXPECT_FALSE(d.m.trip_alarm(0x123));  // not in Table 5.1.1
  EXPECT_EQ(e1_fault_number(0x0B0), 14);
  EXPECT_EQ(e1_fault_number(0xFB2), 77);
}

// Spec §5 "Fault -> S1" and "S1 -> S2": after the acknowledge the drive is
// switching on inhibited, and a PLC that keeps ON and enable operation set
// (an enable held through the fault) stays there; one telegram with OFF1
// (STW1.0 = 0) takes it to S2, then ON + enable operation to S4. MC_Power
// and SinaPos rely on this when they re-enable after a reset.
TEST(Spec5, AfterFaultAcknowledgeSwitchingOnInhibitedUntilOff1) {
  RawDrive d(TelegramType::Hiwin111);
  d.cycle(0x043E);
  d.cycle(0x043F);
  ASSERT_TRUE(d.m.trip_alarm(0x710));
  d.cycle(0x043E);  // OFF1 (no ON, no enable operation) while faulted
  EXPECT_EQ(d.m.state(), State::Fault);
  d.cycle(0x04BE);  // acknowledge: rising edge of bit 7
  EXPECT_EQ(d.m.state(), State::S1);
  EXPECT_EQ(d.zsw1() & 0x004F, 0x0040);  // ZSW1.6 switching on inhibited, b0..b3 = 0
  d.cycle(0x043F, 3);                    // ON + enable operation at once: no
  EXPECT_EQ(d.m.state(), State::S1);
  d.cycle(0x043E);  // OFF1 for one telegram
  EXPECT_EQ(d.m.state(), State::S2);
  d.cycle(0x043F);
  EXPECT_EQ(d.m.state(), State::S4);
}

TEST(Spec10_1, ControllerSignOfLifeLossTripsFb1) {
  RawDrive d(TelegramType::Hiwin111);
  d.cycle(0x043E);
  d.cycle(0x043F);
  // The PLC's counter freezes (e.g. a breakpoint): > PNU 925 (5) failures.
  for (int i = 0; i < 5; ++i) {
    io::store_be<std::uint16_t>(d.out, 0, 0x043F);
    d.m.step(d.now, 1ms, d.out, d.in);
  }
  EXPECT_EQ(d.m.state(), State::S4);
  d.m.step(d.now, 1ms, d.out, d.in);
  EXPECT_EQ(d.m.state(), State::Fault);
  EXPECT_EQ(d.m.fault_code(), 0xFB1);
  // Drive's own counter: 1..15 in ZSW2 bits 12-15.
  const auto s1 = io::load_be<std::uint16_t>(d.in, Telegram111In::kZsw2) >> 12;
  d.cycle(0x043F);
  const auto s2 = io::load_be<std::uint16_t>(d.in, Telegram111In::kZsw2) >> 12;
  EXPECT_EQ(s2, next_sign_of_life(static_cast<std::uint8_t>(s1)));
}

TEST(Spec6_5, ParameterChannelErrorNumbers) {
  RawDrive d(TelegramType::Hiwin111);
  EXPECT_EQ(d.param(rd(pt_pnu(0x317))).values[0], 3000u);
  EXPECT_EQ(d.param(rd(pt_pnu(0x317))).format, 0x06);
  EXPECT_EQ(d.param(rd(922)).values[0], 111u);
  EXPECT_EQ(d.param(rd(930)).values[0], 2u);
  EXPECT_EQ(d.param(rd(964, 0, 7)).values[0], 0x0AAAu);
  EXPECT_EQ(d.param(rd(964, 1)).values[0], 0x05u);
  EXPECT_EQ(d.param_error(rd(0x1234)), 0x00);                     // no such PNU
  EXPECT_EQ(d.param_error(wr(922, 0x06, 9)), 0x01);               // read-only
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x534), 0x06, 1)), 0x02);     // below 2
  EXPECT_EQ(d.param_error(rd(964, 7)), 0x03);                     // Array[7]
  EXPECT_EQ(d.param_error(rd(964, 5, 3)), 0x03);                  // 5..7 > 6
  EXPECT_EQ(d.param_error(rd(pt_pnu(0x317), 1)), 0x04);           // not an array
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x317), 0x04, 3000)), 0x05);  // Int32 to a Uint16
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x317), 0x44, 3000)), 0x17);  // not a value format
  EXPECT_EQ(d.param_error(wr(0x3057, 0x06, 5)), 0x14);            // 1, 2 or 11 only
  EXPECT_EQ(d.param_error(rd(pt_pnu(0x317), 0, 2)), 0x16);        // 2 elements of a simple
  {
    ParamRequest r = rd(pt_pnu(0x317));
    r.attribute = 0x20;
    EXPECT_EQ(d.param_error(r), 0x09);  // description
    r.attribute = 0x30;
    EXPECT_EQ(d.param_error(r), 0x0F);  // text
    r.attribute = 0x10;
    r.do_id = 1;
    EXPECT_EQ(d.param_error(r), 0x19);
    r.do_id = 0;
    r.num_parameters = 2;
    EXPECT_EQ(d.param_error(r), 0x23);
    r.num_parameters = 40;
    EXPECT_EQ(d.param_error(r), 0x22);
    r.num_parameters = 1;
    r.request_id = 0x07;
    const auto resp = d.param(r);
    EXPECT_EQ(resp.response_id, 0x80);
    EXPECT_EQ(resp.error_no, 0x21);
  }
  {
    ParamRequest w = wr(pt_pnu(0x317), 0x06, 2000);
    w.num_elements = 1;
    w.num_values = 2;  // count mismatch
    w.values[1] = 1;
    EXPECT_EQ(d.param_error(w), 0x18);
  }
  // Pt53A has attribute "Setup": not while the pulses are on.
  d.cycle(0x043E);
  d.cycle(0x043F);
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x53A), 0x06, 1)), 0x11);
  // Writes that work: Uint16 and the Word bit string, Float32 general object.
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x534), 0x06, 200)), 0xFFFF);
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x537), 0x42, 300)), 0xFFFF);
  EXPECT_DOUBLE_EQ(d.m.parameter(pt_pnu(0x534)), 200);
  EXPECT_DOUBLE_EQ(d.m.parameter(pt_pnu(0x537)), 300);
  EXPECT_EQ(d.param_error(wr(0x3210, 0x08, double_to_raw(2.5, 0x08))), 0xFFFF);
  EXPECT_FLOAT_EQ(raw_to_double(d.param(rd(0x3210)).values[0], 0x08), 2.5f);
  // The response is fetched once; a read before a request is refused.
  std::array<std::uint8_t, 240> b{};
  std::size_t len = 0;
  EXPECT_EQ(d.m.read_record(kParamRecordIndex, b, len), io::RecordError::InvalidState);
  EXPECT_EQ(d.m.read_record(0x1234, b, len), io::RecordError::InvalidIndex);
  // The PROFINET local index works too.
  EXPECT_EQ(d.param(rd(922), kParamRecordIndexLocal).values[0], 111u);
}

TEST(Spec6_3, PowerCycleParametersTakeEffectAfterRestart) {
  RawDrive d(TelegramType::Standard3);
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x316), 0x06, 1000)), 0xFFFF);
  EXPECT_EQ(d.param(rd(pt_pnu(0x316))).values[0], 1000u);
  // Active value still 10000 rpm: 150 % of 3000 rpm is not clamped.
  d.cycle(0x047E);
  io::store_be<std::int32_t>(d.out, Telegram3Out::kNsollB, 0x60000000);
  d.cycle(0x047F, 400);
  EXPECT_NEAR(cu_per_s_to_rpm(d.m.velocity(), 10000), 4500, 5);
  d.m.power_cycle();  // not saved to flash: back to the default
  EXPECT_EQ(d.param(rd(pt_pnu(0x316))).values[0], 10000u);
  EXPECT_EQ(d.param_error(wr(pt_pnu(0x316), 0x06, 1000)), 0xFFFF);
  EXPECT_EQ(d.param_error(wr(0x3215, 0x03, 1)), 0xFFFF);  // warm reset keeps RAM
  EXPECT_FALSE(d.m.answering());
  d.cycle(0x0000, 200);
  EXPECT_TRUE(d.m.answering());
  d.cycle(0x047E);
  io::store_be<std::int32_t>(d.out, Telegram3Out::kNsollB, 0x60000000);
  d.cycle(0x047F, 400);
  EXPECT_NEAR(cu_per_s_to_rpm(d.m.velocity(), 10000), 1000, 5);  // clamped by Pt316
}

TEST(Spec7_10, MultiTurnClearAndAbsoluteEncoderAcrossPowerCycle) {
  HiwinE1Config c;
  c.initial_position = 123456.0;  // 12 turns + 3456 CU
  RawDrive d(TelegramType::Hiwin111, c);
  EXPECT_EQ(d.m.multi_turn(), 12);
  d.m.power_cycle();
  EXPECT_EQ(d.m.multi_turn(), 12);  // battery-backed
  EXPECT_DOUBLE_EQ(d.m.encoder_position(), 123456.0);
  // Refused while enabled.
  d.cycle(0x043E);
  d.cycle(0x043F);
  EXPECT_EQ(d.param_error(wr(0x3200, 0x04, 1)), 0xFFFF);
  EXPECT_EQ(d.param(rd(0x3200)).values[0], 16u);
  EXPECT_EQ(d.param_error(wr(0x3200, 0x04, 2)), 0x02);  // only 0..1 may be written
  d.cycle(0x043E, 5);
  EXPECT_EQ(d.param_error(wr(0x3200, 0x04, 1)), 0xFFFF);
  EXPECT_EQ(d.param(rd(0x3200)).values[0], 2u);
  d.cycle(0x043E, 600);
  EXPECT_EQ(d.param(rd(0x3200)).values[0], 4u);
  EXPECT_EQ(d.m.multi_turn(), 0);
  EXPECT_DOUBLE_EQ(d.m.encoder_position(), 3456.0);
  d.m.power_cycle();
  EXPECT_DOUBLE_EQ(d.m.encoder_position(), 3456.0);
  // Failure (32), e.g. the encoder refuses.
  d.m.fail_next_multiturn_clear();
  d.param(wr(0x3200, 0x04, 1));
  d.cycle(0x043E, 600);
  EXPECT_EQ(d.param(rd(0x3200)).values[0], 32u);
}

TEST(Spec7_10, IncrementalEncoderLosesPositionAndCannotClear) {
  HiwinE1Config c;
  c.absolute_encoder = false;
  c.initial_position = 5000;
  RawDrive d(TelegramType::Hiwin111, c);
  EXPECT_DOUBLE_EQ(d.m.encoder_position(), 0);  // incremental: 0 at power-up
  d.param(wr(0x3200, 0x04, 1));
  d.cycle(0x043E, 600);
  EXPECT_EQ(d.param(rd(0x3200)).values[0], 32u);
}

TEST(ModelParams, RegistryAndParams) {
  const auto* f = io::DeviceModelRegistry::instance().find("hiwin_e1");
  ASSERT_NE(f, nullptr);
  io::ModelParams p;
  p.set("telegram", "9");
  p.set("cu_per_rev", "4096");
  auto m = (*f)(p);
  EXPECT_EQ(m->input_size(), 10u);
  EXPECT_EQ(m->output_size(), 20u);
  io::ModelParams bad;
  bad.set("telegram", "1");
  EXPECT_THROW((*f)(bad), io::ParamError);
  io::ModelParams typo;
  typo.set("telegramm", "3");
  EXPECT_THROW((*f)(typo), io::ParamError);
}

}  // namespace plc::sim
