// The safety blocks declare their fields for reflection (debugger, HMI,
// trace): every F-I/O DB signal is listed, in order, under its vendor name.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

#include "plc/fb/safety/nord_safe_io.hpp"

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

}  // namespace
