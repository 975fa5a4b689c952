// Explicit services of the simulated VF66B (query_record; mapping of
// plc/io/explicit_message.hpp) against the attribute tables of
// toyo-vf66-devicenet.md §3-§6 and the error codes of §11.1 (Table 5.2).
// Requests are literal bytes in the 8/8 body format (§1.4): class,
// instance, attribute, data.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "plc/io/explicit_message.hpp"
#include "vf66b/vf66b_model.hpp"

namespace plc::sim {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

namespace {

struct Answer {
  io::RecordError error = io::RecordError::None;
  Bytes data;
  // The §11.1 general status of an Error Response, 0 for success.
  [[nodiscard]] int general() const {
    const auto c = static_cast<std::uint16_t>(error);
    return c >= 0x100 ? (c >> 8) : (c == 0 ? 0 : -static_cast<int>(c));
  }
};

struct Drive {
  explicit Drive(unsigned j09 = 1, unsigned j10 = 1) {
    Vf66bConfig c;
    c.j09 = j09;
    c.j10 = j10;
    c.b10 = 3;
    c.b11 = 3;
    c.startup_time = 10ms;
    c.accel_time_s = 1;
    c.decel_time_s = 1;
    m = std::make_unique<Vf66bModel>(c);
    out.assign(m->output_size(), 0);
    in.assign(m->input_size(), 0);
    step(20);
  }
  void step(int n = 1) {
    for (int i = 0; i < n; ++i) {
      now += 1ms;
      m->step(now, 1ms, out, in);
    }
  }
  Answer call(std::uint16_t index, const Bytes& req) {
    std::array<std::uint8_t, io::kRecordMaxBytes> buf{};
    std::size_t len = 0;
    Answer a;
    a.error = m->query_record(index, req, buf, len);
    a.data.assign(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(len));
    return a;
  }
  Answer get(std::uint8_t cls, std::uint8_t inst, std::uint8_t attr) {
    return call(0xD00E, {cls, inst, attr});
  }
  Answer set(std::uint8_t cls, std::uint8_t inst, std::uint8_t attr, const Bytes& data) {
    Bytes req = {cls, inst, attr};
    req.insert(req.end(), data.begin(), data.end());
    return call(0xD010, req);
  }
  std::unique_ptr<Vf66bModel> m;
  Bytes out, in;
  TIME now{};
};

}  // namespace

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

TEST(Vf66bExplicit, AssemblyCarriedDataRefuseSet_Section7_3) {
  Drive d21(1, 1);
  EXPECT_EQ(d21.set(0x29, 1, 3, {1}).general(), 0x10) << "Run1 is in assembly 21";
  EXPECT_EQ(d21.set(0x29, 1, 5, {1}).general(), 0x10) << "NetCtrl is in assembly 21";
  EXPECT_EQ(d21.set(0x2A, 1, 8, {0, 1}).general(), 0x10) << "SpeedRef is in assembly 21";
  EXPECT_EQ(d21.set(0x29, 1, 12, {1}).general(), 0x10) << "FaultRst is in assembly 21";
  Drive d20(0, 0);
  EXPECT_EQ(d20.set(0x29, 1, 5, {0}).general(), 0) << "assembly 20 has no NetCtrl bit";
  d20.step();
  EXPECT_EQ(d20.get(0x29, 1, 15).data, Bytes{0}) << "CtrlFromNet follows the request";
  EXPECT_EQ(d20.set(0x29, 1, 5, {1}).general(), 0);
  // Run2 is not in assembly 20: set through the object it is an event of
  // Table 3.4.3 (Run1 = 0 from the assembly).
  d20.out = {0, 0, 0x00, 0x10};  // 512 rpm
  EXPECT_EQ(d20.set(0x29, 1, 4, {1}).general(), 0);
  d20.step(400);
  EXPECT_EQ(d20.m->state(), acdrive::DriveState::Enabled);
  EXPECT_DOUBLE_EQ(d20.m->speed_rpm(), -512);
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
