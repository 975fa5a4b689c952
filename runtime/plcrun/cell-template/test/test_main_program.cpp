// The program in virtual time: the clock advances one period per scan, so
// 10 s of cell time take milliseconds and every run is the same.
#include <gtest/gtest.h>

#include "plc/cell_config.hpp"
#include "plc/runtime.hpp"

namespace {

// cell.yaml, with the library this build made.
const std::string kCell = R"(
libraries: [)" MYCELL_LIBRARY R"(]
tasks:
  - name: main
    period: 10ms
    programs: [Main]
programs:
  - name: Main
    type: MainProgram
)";

std::string value(plc::Runtime& rt, const char* path) {
  const plc::VarInfo* v = rt.vars().find(path);
  return v ? plc::VarRegistry::format(*v) : "<no such variable>";
}

TEST(MainProgram, BlinksOncePerSecondInVirtualTime) {
  plc::Runtime rt(plc::parse_cell_config(kCell, "test.yaml"));
  rt.run(plc::io::ClockMode::Virtual, std::chrono::seconds(10));
  // On after 0.5 s, then one blink per second (on 0.5 s, off 0.5 s).
  EXPECT_EQ(value(rt, "Main.blinks"), "10");
}

TEST(MainProgram, DisabledStaysDark) {
  plc::CellConfig cfg = plc::parse_cell_config(kCell, "test.yaml");
  plc::Runtime rt(cfg);
  ASSERT_EQ(plc::VarRegistry::write_text(*rt.vars().find("Main.enable"), "FALSE"), "");
  rt.run(plc::io::ClockMode::Virtual, std::chrono::seconds(10));
  EXPECT_EQ(value(rt, "Main.blinks"), "0");
}

}  // namespace
