// The safety blocks declare their fields for reflection (debugger, HMI,
// trace): every F-I/O DB signal is listed, in order, under its vendor name.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

#include "plc/fb/safety/nord_safe_io.hpp"
#include "plc/field_visitor.hpp"

namespace {

struct NameCollector {
  std::vector<std::string> names;
  template <class T>
  void operator()(const char* name, T&) {
    names.emplace_back(name);
  }
};

TEST(SafetyReflect, FModuleListsFIoDbSignals_Anchors4_4) {
  plc::safety::F_MODULE<4, 4> fm;
  NameCollector c;
  fm.reflect(c);
  for (const char* n : {"port", "PASS_ON", "ACK_NEC", "ACK_REI", "IPAR_EN", "PASS_OUT", "QBAD",
                        "ACK_REQ", "IPAR_OK", "DIAG", "VS_IN", "F_WD_Time"}) {
    EXPECT_NE(std::find(c.names.begin(), c.names.end(), n), c.names.end()) << n;
  }
}

TEST(SafetyReflect, NordSafeIoListsNestedModuleAndBits_Spec2_3_2_4) {
  plc::safety::NORD_SAFE_IO io;
  NameCollector c;
  io.reflect(c);
  ASSERT_FALSE(c.names.empty());
  EXPECT_EQ(c.names.front(), "FMOD");
  for (const char* n :
       {"OSSD1", "SLS_LEVEL", "CH_PASS_ACK", "OSSD1_OFF", "CLOCK2_OFF", "SI2", "SSM", "SSR_OK"}) {
    EXPECT_NE(std::find(c.names.begin(), c.names.end(), n), c.names.end()) << n;
  }
}

// Issue 10 point 5: the F-host's protocol state (PDU lengths, consecutive
// numbers, the state machine) and the blocks' own state are read-only for
// the debugger, the HMI and init: (a forced PDU length overflowed the stack
// buffer of safety_pdu.hpp); the F-I/O DB signals stay writable.
TEST(SafetyReflect, InternalStateIsReadOnlyTheFIoDbSignalsWritable) {
  plc::safety::NORD_SAFE_IO io;
  const plc::FieldVisitor v = plc::collect_fields("io", io);
  int internal_fields = 0;
  for (const auto& f : v.fields) {
    const std::string& p = f.path;
    const bool internal =
        p.ends_with('_') || p.find("_.") != std::string::npos || p.find("_[") != std::string::npos;
    EXPECT_EQ(f.access.read_only, internal) << p;
    internal_fields += internal;
  }
  EXPECT_GT(internal_fields, 25);
  for (const char* p :
       {"io.FMOD.proto_.out_len_", "io.FMOD.proto_.in_len_", "io.FMOD.phase_", "io.ack_cn_"}) {
    EXPECT_TRUE(std::any_of(v.fields.begin(), v.fields.end(), [&](const auto& f) {
      return f.path == p && f.access.read_only;
    })) << p;
  }
}

}  // namespace
