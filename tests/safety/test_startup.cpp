// Start-up of F-host and simulated NORD F-device (spec nord-profisafe.md
// §2.2 F-parameters at start-up, §8.2 start-up steps 1-4).
#include <gtest/gtest.h>

#include "plc/fb/safety/f_host_diag.hpp"
#include "safety_rig.hpp"

namespace {

using namespace safety_test;
using plc::safety::FHostState;

// §8.2 start-up: F-parameters written by record, then R_cons_nr exchange, then
// automatic reintegration at first start; QBAD/PASS_OUT are 1 until then.
TEST(SafetyStartup, ParametersThenAutomaticReintegration_Spec8_2) {
  Rig r;
  EXPECT_TRUE(r.io.QBAD);
  EXPECT_TRUE(r.io.PASS_OUT);
  r.scan();
  EXPECT_EQ(r.io.FMOD.STATE, FHostState::Param);
  EXPECT_TRUE(r.io.QBAD);
  const int n = r.scan_until([&] { return r.running(); }, 20);
  ASSERT_GT(n, 0);
  EXPECT_TRUE(r.model->fparams_ok());
  EXPECT_FALSE(r.io.PASS_OUT);
  EXPECT_FALSE(r.io.ACK_REQ);
  EXPECT_EQ(r.io.DIAG, 0);
  // The block sent the 14-byte block of §2.2 with the host's values.
  const auto& b = r.io.FMOD.fparam_block();
  EXPECT_EQ(b[0], 0x08);
  EXPECT_EQ(b[1], 0x48);
  EXPECT_EQ(b[3], 10);   // F_Source_Add
  EXPECT_EQ(b[5], 1);    // F_Dest_Add
  EXPECT_EQ(b[7], 100);  // F_WD_Time
}

// §2.3/§2.4: OSSD1 commanded on reaches SO1; the device reports the inverted
// OSSD bits, SI1/SI2 and SSM; OSSDn_ON is gated by QBAD.
TEST(SafetyStartup, NordBitsBothWays_Spec2_3_2_4) {
  Rig r;
  r.model->set_si(true, false);
  r.io.OSSD1 = true;
  r.io.OSSD3 = true;
  r.scan(10);
  ASSERT_TRUE(r.running());
  EXPECT_TRUE(r.model->ossd(0));
  EXPECT_FALSE(r.model->ossd(1));
  EXPECT_TRUE(r.model->ossd(2));
  EXPECT_FALSE(r.io.OSSD1_OFF);
  EXPECT_TRUE(r.io.OSSD2_OFF);
  EXPECT_FALSE(r.io.OSSD3_OFF);
  EXPECT_TRUE(r.io.OSSD1_ON);
  EXPECT_FALSE(r.io.OSSD2_ON);
  EXPECT_FALSE(r.io.CLOCK1_OFF);  // clocks enabled (P802[6], [7])
  EXPECT_TRUE(r.io.SI1);
  EXPECT_FALSE(r.io.SI2);
  EXPECT_TRUE(r.io.SSM);  // speed 0 <= max SSM (Out 1.7, spec [AMBIG] reading)
  // Raw bytes, spec §2.4: Out 0.0 = 0 (OSSD1 on), Out 3.0 = 1 (OSSD2 off),
  // Out 3.4 = SI1, Out 1.7 = SSM.
  EXPECT_EQ(r.io.FMOD.IN_DATA[0] & 0x01, 0);
  EXPECT_EQ(r.io.FMOD.IN_DATA[3] & 0x01, 0x01);
  EXPECT_EQ(r.io.FMOD.IN_DATA[3] & 0x10, 0x10);
  EXPECT_EQ(r.io.FMOD.IN_DATA[1] & 0x80, 0x80);
  // Request bytes, spec §2.3: In 0.0 and In 3.1.
  EXPECT_EQ(r.io.FMOD.OUT_DATA[0], 0x01);
  EXPECT_EQ(r.io.FMOD.OUT_DATA[3], 0x02);
}

// §8.3: F-address from P831 when the DIP value is 0.
TEST(SafetyStartup, FAddressFromP831WhenDipZero_Spec6_4) {
  Rig r({{"dip_address", "0"}, {"p831", "42"}});
  r.io.FMOD.F_Dest_Add = 42;
  r.scan(10);
  EXPECT_EQ(r.model->f_address(), 42);
  EXPECT_TRUE(r.running());
}

}  // namespace
