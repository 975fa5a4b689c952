// F-parameter checks of the simulated NORD device (spec nord-profisafe.md
// §5.5 F-parameter error table, §8.3 validation table, §8.4 items 4 and 5):
// each error is reported with its 57xx code, blocks cyclic exchange, and the
// F-host shows it as an F-parameter error with the code.
#include <gtest/gtest.h>

#include <array>

#include "plc/fb/safety/f_host_diag.hpp"
#include "plc/fb/safety/f_parameters.hpp"
#include "plc/fb/safety/nord_error_codes.hpp"
#include "safety_rig.hpp"

namespace {

using namespace safety_test;
using plc::safety::FHostState;
namespace diag = plc::safety::diag;
namespace err = plc::safety::nord::err;
namespace ps = plc::safety;

// The host is refused, stays passivated, never exchanges cyclic data.
void expect_refused(Rig& r, std::uint16_t code) {
  r.scan(50);
  EXPECT_EQ(r.io.FMOD.STATE, FHostState::Param);
  EXPECT_TRUE(r.io.DIAG & diag::kFParError);
  EXPECT_EQ(r.io.DIAG_CODE, code);
  EXPECT_EQ(r.model->current_code(), code);
  EXPECT_FALSE(r.model->fparams_ok());
  EXPECT_TRUE(r.all_safe());
  EXPECT_TRUE(r.io.PASS_OUT);
}

TEST(SafetyFParamErrors, DestMismatch5711ThenFixedAfterRetry_Spec5_5) {
  Rig r;
  r.io.FMOD.F_Dest_Add = 7;
  r.io.OSSD1 = true;
  expect_refused(r, err::kDestMismatch);
  r.io.FMOD.F_Dest_Add = 1;  // retried once a second; start-up then automatic
  ASSERT_GT(r.scan_until([&] { return r.running(); }, 1200), 0);
  EXPECT_EQ(r.model->previous_code(), err::kDestMismatch);
}
TEST(SafetyFParamErrors, DestInvalid5712_Above255_Spec5_5) {
  Rig r;
  r.io.FMOD.F_Dest_Add = 300;
  expect_refused(r, err::kDestInvalid);
}
TEST(SafetyFParamErrors, DestInvalid5712_Zero_Spec8_4_4) {
  Rig r;
  r.io.FMOD.F_Dest_Add = 0;
  expect_refused(r, err::kDestInvalid);
}
TEST(SafetyFParamErrors, SourceInvalid5713_Zero_Spec8_4_4) {
  Rig r;
  r.io.FMOD.F_Source_Add = 0;
  expect_refused(r, err::kSourceInvalid);
}
TEST(SafetyFParamErrors, SourceInvalid5713_65535_Spec8_4_4) {
  Rig r;
  r.io.FMOD.F_Source_Add = 65535;
  expect_refused(r, err::kSourceInvalid);
}
TEST(SafetyFParamErrors, WatchdogZero5714_Spec5_5) {
  Rig r;
  r.io.FMOD.F_WD_Time = 0;
  expect_refused(r, err::kWatchdogZero);
}
// Device supporting SIL 2 only (max_sil), host asks SIL 3.
TEST(SafetyFParamErrors, SilTooHigh5715_Spec5_5) {
  Rig r(Params{{"max_sil", "2"}});
  r.io.FMOD.F_SIL = static_cast<plc::USINT>(ps::FSil::Sil3);
  expect_refused(r, err::kSilTooHigh);
}
TEST(SafetyFParamErrors, IparCrc5719_Spec5_5) {
  Rig r;
  r.io.FMOD.F_iPar_CRC = 0x1234ABCE;
  expect_refused(r, err::kIparCrc);
}

// Fixed-value errors the F_MODULE never produces: written as raw records.
std::uint16_t write_raw(plc::sim::NordProfisafeModel& m, ps::FParameters p, bool fill = true) {
  std::array<std::uint8_t, ps::kFParamBlockSize> b{};
  ps::encode(p, b, fill);
  return static_cast<std::uint16_t>(m.write_record(ps::kFParamRecordIndex, b));
}
ps::FParameters good() {
  ps::FParameters p;
  p.source_add = 10;
  p.dest_add = 1;
  p.ipar_crc = 0x1234ABCD;
  return p;
}

TEST(SafetyFParamErrors, RawGoodBlockAccepted_Spec8_3) {
  Rig r;
  EXPECT_EQ(write_raw(*r.model, good()), 0);
  EXPECT_TRUE(r.model->fparams_ok());
}
TEST(SafetyFParamErrors, ParVersion5716_Spec8_4_5) {
  Rig r;
  auto p = good();
  p.par_version = 0;
  EXPECT_EQ(write_raw(*r.model, p), err::kParVersion);
  EXPECT_FALSE(r.model->fparams_ok());
}
TEST(SafetyFParamErrors, ParCrc5717_Spec8_4_5) {
  Rig r;
  auto p = good();
  std::array<std::uint8_t, ps::kFParamBlockSize> b{};
  ps::encode(p, b);
  p.par_crc = static_cast<std::uint16_t>(p.par_crc ^ 0x0100);
  EXPECT_EQ(write_raw(*r.model, p, false), err::kParCrc);
}
TEST(SafetyFParamErrors, CrcLength5721_Spec8_4_5) {
  Rig r;
  for (std::uint8_t len : {1, 2}) {
    auto p = good();
    p.crc_length = len;
    EXPECT_EQ(write_raw(*r.model, p), err::kCrcLength) << int(len);
  }
}
TEST(SafetyFParamErrors, BlockId5718_Spec5_5) {
  Rig r;
  auto p = good();
  p.block_id = 0;
  EXPECT_EQ(write_raw(*r.model, p), err::kParGeneral);
}
// 5725 is fatal (f): the device stays faulted until power cycle.
TEST(SafetyFParamErrors, TruncatedRecord5725Fatal_Spec8_4_5) {
  Rig r;
  std::array<std::uint8_t, 12> b{};
  EXPECT_EQ(static_cast<std::uint16_t>(r.model->write_record(ps::kFParamRecordIndex, b)),
            err::kParTelegram);
  EXPECT_TRUE(r.model->fatal());
  r.model->power_cycle();
  EXPECT_FALSE(r.model->fatal());
}
// §8.3: effective F-address 0 or 65535 is refused (DIP fatal 5726).
TEST(SafetyFParamErrors, FAddressZeroIsFatal5726_Spec8_3) {
  Rig r({{"dip_address", "0"}, {"p831", "0"}});
  EXPECT_TRUE(r.model->fatal());
  EXPECT_EQ(r.model->current_code(), err::kDipRead);
  Rig r2({{"dip_address", "0"}, {"p831", "65535"}});
  EXPECT_EQ(r2.model->current_code(), err::kDipRead);
}

// §5.5 / §8.3: a device without a valid F-address (DIP/P831 read error,
// fatal 5726) cannot compare F_Dest_Add with anything. The F-host's
// parameter write is refused with 5726 itself, and the program sees 5726,
// not a 5711 made up from the missing address; P841 keeps 5726 (the FE LED
// blinks it) and the refusal does not push it into P842.
TEST(SafetyFParamErrors, MissingFAddress5726ReachesProgram_Spec5_5_8_3) {
  for (const Params& pm : {Params{{"dip_address", "0"}, {"p831", "0"}},
                           Params{{"dip_address", "0"}, {"p831", "65535"}}}) {
    Rig r(pm);
    r.io.OSSD1 = true;
    r.scan(50);
    EXPECT_EQ(r.io.FMOD.STATE, FHostState::Param);
    EXPECT_TRUE(r.io.DIAG & diag::kFParError);
    EXPECT_EQ(r.io.DIAG_CODE, err::kDipRead);
    EXPECT_EQ(r.model->current_code(), err::kDipRead);
    EXPECT_EQ(r.model->previous_code(), 0);
    EXPECT_TRUE(r.all_safe());
    r.scan(1500);  // the write is retried once a second: same answer
    EXPECT_EQ(r.io.DIAG_CODE, err::kDipRead);
    EXPECT_EQ(r.model->current_code(), err::kDipRead);
  }
}

// Same mistake, other path (§5.5 types q/f): after the fatal 5725 a later
// refused block still answers with its own number (here 5711), but it must
// not push the latched fatal code out of P841: the device stays in its fatal
// fault until a power cycle and keeps showing (and blinking) 5725.
TEST(SafetyFParamErrors, FatalCodeStaysCurrentAfterLaterRefusal_Spec5_5) {
  Rig r;
  std::array<std::uint8_t, 12> shortb{};
  ASSERT_EQ(static_cast<std::uint16_t>(r.model->write_record(ps::kFParamRecordIndex, shortb)),
            err::kParTelegram);
  auto p = good();
  p.dest_add = 7;
  EXPECT_EQ(write_raw(*r.model, p), err::kDestMismatch);
  EXPECT_EQ(r.model->current_code(), err::kParTelegram);
  EXPECT_TRUE(r.model->fatal());
}

// §4.5 / §5.5: out-of-range i-parameters are fatal configuration errors.
TEST(SafetyFParamErrors, IParameterRangeErrorsAreFatal_Spec5_5) {
  struct Case {
    const char* key;
    const char* value;
    std::uint16_t code;
  };
  const Case cases[] = {
      {"p802_1", "2", err::kP802Range},      {"p804", "9", err::kP804Range},
      {"p805", "1", err::kP805Range},        {"p800_1", "3", err::kP800Range},
      {"p803", "30001", err::kP803Range},    {"p801", "2", err::kP801Range},
      {"p812", "18", err::kEncoderParRange}, {"p821_1", "61", err::kP821Range},
      {"p822_2", "-1", err::kP822Range},     {"p823_6", "2500", err::kP823Range},
      {"p824_3", "10000", err::kP824Range},  {"p823_4", "9999", err::kLimitFrequency},
  };
  for (const auto& c : cases) {
    Rig r(Params{{c.key, c.value}});
    EXPECT_TRUE(r.model->fatal()) << c.key;
    EXPECT_EQ(r.model->current_code(), c.code) << c.key;
  }
  // P820 on with the encoder off: the (f) variant of 5756-5761.
  Rig r(Params{{"p810", "0"}});
  EXPECT_EQ(r.model->current_code(), err::kSls);
}

}  // namespace
