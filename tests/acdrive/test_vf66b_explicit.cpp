// Explicit services of the simulated VF66B (query_record; mapping of
// plc/io/explicit_message.hpp) against the attribute tables of
// toyo-vf66-devicenet.md §3-§6 and the error codes of §11.1 (Table 5.2).
// Requests are literal bytes in the 8/8 body format (§1.4): class,
// instance, attribute, data.
#include <gtest/gtest.h>

#include "vf66b_explicit_harness.hpp"

namespace plc::sim {

using namespace std::chrono_literals;
using test::Answer;
using test::Bytes;
using test::Drive;

TEST(Vf66bExplicit, GetSupportedAttributes_Table3_3_2_Table3_4_2_Table3_5_2) {
  Drive d;
  EXPECT_EQ(d.get(0x29, 1, 15).data, Bytes{0}) << "CtrlFromNet: assembly 21 sends NetCtrl = 0";
  d.out = {0x60, 0, 0, 0};  // NetCtrl, NetRef
  d.step();
  EXPECT_EQ(d.get(0x28, 1, 3).data, Bytes{7}) << "MotorType, USINT: squirrel-cage induction";
  EXPECT_EQ(d.get(0x28, 1, 6).data, (Bytes{100, 0})) << "RatedCurrent, UINT (100 mA)";
  EXPECT_EQ(d.get(0x28, 1, 7).data, (Bytes{200, 0})) << "RatedVoltage, UINT";
  EXPECT_EQ(d.get(0x29, 1, 6).data, Bytes{3}) << "State Ready";
  EXPECT_EQ(d.get(0x29, 1, 9).data, Bytes{1}) << "Ready";
  EXPECT_EQ(d.get(0x29, 1, 10).data, Bytes{0}) << "Faulted";
  EXPECT_EQ(d.get(0x29, 1, 11).data, Bytes{0}) << "Warning";
  EXPECT_EQ(d.get(0x29, 1, 15).data, Bytes{1}) << "CtrlFromNet (b-11 = 3, NetCtrl)";
  EXPECT_EQ(d.get(0x2A, 1, 6).data, Bytes{2}) << "DriveMode closed-loop speed (vector)";
  EXPECT_EQ(d.get(0x2A, 1, 22).data, Bytes{3}) << "SpeedScale = J-11";
  EXPECT_EQ(d.get(0x2A, 1, 29).data, Bytes{1}) << "RefFromNet (b-10 = 3)";
  // Run forward at 900 rpm: SpeedRef/SpeedActual 7200 = 0x1C20 (§6.1).
  d.out = {0x61, 0, 0x20, 0x1C};
  d.step(600);
  EXPECT_EQ(d.get(0x2A, 1, 7).data, (Bytes{0x20, 0x1C}));
  EXPECT_EQ(d.get(0x2A, 1, 8).data, (Bytes{0x20, 0x1C}));
  EXPECT_EQ(d.get(0x2A, 1, 3).data, Bytes{1}) << "AtReference";
  EXPECT_EQ(d.get(0x29, 1, 3).data, Bytes{1}) << "Run1";
  EXPECT_EQ(d.get(0x29, 1, 7).data, Bytes{1}) << "Running1";
  EXPECT_EQ(d.get(0x29, 1, 8).data, Bytes{0}) << "Running2";
  EXPECT_EQ(d.get(0x29, 1, 6).data, Bytes{4}) << "Enabled";
}

TEST(Vf66bExplicit, ParameterObjectMirrorsTheProfile_Table3_2) {
  Drive d;
  d.out = {0x62, 0, 0x00, 0x10};  // Run2, 0x1000 = 512 rpm
  d.step(400);
  EXPECT_EQ(d.get(0x0F, 1, 1).data, Bytes{7}) << "1 Motor Type";
  EXPECT_EQ(d.get(0x0F, 5, 1).data, Bytes{4}) << "5 Drive State";
  EXPECT_EQ(d.get(0x0F, 7, 1).data, Bytes{1}) << "7 Running Rev";
  EXPECT_EQ(d.get(0x0F, 16, 1).data, (Bytes{0x00, 0xF0})) << "16 Speed Actual = -4096";
  EXPECT_EQ(d.get(0x0F, 18, 1).data, Bytes{3}) << "18 Speed Scale";
  EXPECT_EQ(d.get(0x0F, 19, 1).data, Bytes{1}) << "19 Ref From Net";
  EXPECT_EQ(d.get(0x0F, 20, 1).general(), 0x16) << "no instance 20";
  EXPECT_EQ(d.get(0x0F, 1, 2).general(), 0x14) << "only attribute 1 (Parameter Value)";
  EXPECT_EQ(d.set(0x0F, 1, 1, {5}).general(), 0) << "Motor Type is Set/Get";
  EXPECT_EQ(d.get(0x28, 1, 3).data, Bytes{5});
  EXPECT_EQ(d.set(0x0F, 5, 1, {3}).general(), 0x0E) << "Drive State is Get only";
}

TEST(Vf66bExplicit, NotSupportedAttributesAnswer0x14_Section13_1_4) {
  Drive d;
  for (std::uint8_t cls : {0x28, 0x29, 0x2A})
    for (std::uint8_t a : {1, 2, 6, 7})
      EXPECT_EQ(d.get(cls, 0, a).general(), 0x14) << "class attribute " << int(a);
  EXPECT_EQ(d.get(0x28, 1, 1).general(), 0x14) << "NumAttr";
  EXPECT_EQ(d.get(0x28, 1, 2).general(), 0x14) << "Attributes";
  EXPECT_EQ(d.get(0x28, 1, 8).general(), 0x14) << "RatedPower";
  EXPECT_EQ(d.get(0x29, 1, 13).general(), 0x14) << "FaultCode (§13.2.7)";
  EXPECT_EQ(d.get(0x29, 1, 16).general(), 0x14) << "DNFaultMode";
  EXPECT_EQ(d.get(0x2A, 1, 9).general(), 0x14) << "CurrentActual";
  EXPECT_EQ(d.get(0x2A, 1, 23).general(), 0x14) << "CurrentScale";
  EXPECT_EQ(d.set(0x2A, 1, 18, {0, 0}).general(), 0x14) << "AccelTime";
}

TEST(Vf66bExplicit, UnknownObjectsAndServices_Section11_1) {
  Drive d;
  EXPECT_EQ(d.get(0x29, 2, 6).general(), 0x16) << "instance 2";
  EXPECT_EQ(d.get(0x64, 1, 1).general(), 0x16) << "no vendor class (§2)";
  EXPECT_EQ(d.get(0x01, 1, 1).general(), 0x16) << "Identity belongs to the hosting slave";
  EXPECT_EQ(d.call(0xD001, {0x29, 1}).general(), 0x08) << "Get_Attributes_All";
  EXPECT_EQ(d.call(0xD005, {0x29, 1}).general(), 0x08) << "Reset";
  EXPECT_EQ(d.call(0xD00E, {0x29, 1}).general(), 0x13) << "path without attribute";
  EXPECT_EQ(d.call(0xD00E, {0x29, 1, 6, 0}).general(), 0x15) << "Get with data";
  EXPECT_EQ(d.call(0x002F, {0x29, 1, 6}).error, io::RecordError::InvalidIndex);
}

TEST(Vf66bExplicit, SetChecksAccessLengthAndValue_Section11_1) {
  Drive d(0, 0);
  EXPECT_EQ(d.set(0x29, 1, 6, {3}).general(), 0x0E) << "State is Get";
  EXPECT_EQ(d.set(0x2A, 1, 7, {0, 0}).general(), 0x0E) << "SpeedActual is Get";
  EXPECT_EQ(d.set(0x28, 1, 6, {1}).general(), 0x13) << "UINT needs 2 bytes";
  EXPECT_EQ(d.set(0x28, 1, 3, {1, 0}).general(), 0x15) << "USINT takes 1 byte";
  EXPECT_EQ(d.set(0x28, 1, 3, {}).general(), 0x13);
  EXPECT_EQ(d.set(0x28, 1, 3, {11}).general(), 0x09) << "MotorType 0..10";
  EXPECT_EQ(d.set(0x29, 1, 5, {2}).general(), 0x09) << "BOOL 0 or 1";
  EXPECT_EQ(d.set(0x2A, 1, 6, {1}).general(), 0x09) << "the inverter is in vector mode";
  EXPECT_EQ(d.set(0x2A, 1, 6, {2}).general(), 0);
  EXPECT_EQ(d.set(0x28, 1, 6, {0x2C, 0x01}).general(), 0);
  EXPECT_EQ(d.get(0x28, 1, 6).data, (Bytes{0x2C, 0x01})) << "30.0 A";
}

TEST(Vf66bExplicit, SpeedScaleSetWhileStoppedOnlyAndVolatile_Section9_1) {
  Drive d;
  EXPECT_EQ(d.set(0x2A, 1, 22, {2}).general(), 0);
  d.out = {0x61, 0, 0x00, 0x10};  // 0x1000 at scale 2 = 1024 rpm
  d.step(700);
  EXPECT_DOUBLE_EQ(d.m->speed_rpm(), 1024);
  EXPECT_EQ(d.set(0x2A, 1, 22, {3}).general(), 0x10) << "J-11 not changeable while running";
  EXPECT_EQ(d.set(0x2A, 1, 22, {0x80}).general(), 0x10);
  d.m->power_cycle();
  EXPECT_EQ(d.get(0x2A, 1, 22).data, Bytes{3}) << "power-up reloads J-11";
}

}  // namespace plc::sim
