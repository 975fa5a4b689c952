// Every class of cell-config error is reported as file:line:column naming
// the key, with exit code 2, before anything starts (issue 2 acceptance).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "test_helpers.hpp"

namespace {

const char* kGood = R"(cell: t
tasks:
  - name: main
    period: 1ms
    programs: [Tank]
programs:
  - name: Tank
    type: TankCycle
plugins:
  - name: sim
    type: sim
devices:
  - name: echo
    plugin: sim
    model: loopback
    input: "%IB0"
    output: "%QB0"
    params: {size: 4}
)";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  // Runs during static initialisation: a typo in a case must not go unseen.
  if (pos == std::string::npos) {
    std::fprintf(stderr, "test_config_errors: pattern not found in kGood: %s\n", from.c_str());
    std::abort();
  }
  s.replace(pos, from.size(), to);
  return s;
}

// kGood with another device model and parameters.
std::string with_model(const std::string& model, const std::string& params) {
  return replaced(replaced(kGood, "model: loopback", "model: " + model), "{size: 4}", params);
}

struct Case {
  const char* name;
  std::string yaml;
  int line;             // expected line (1-based)
  const char* key;      // the message must name it
  const char* message;  // and say this
};

// Readable test names in failures instead of a byte dump.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class ConfigErrors : public ::testing::TestWithParam<Case> {};

TEST_P(ConfigErrors, PlcrunReportsFileLineKeyAndExitsWithTwo) {
  const Case& c = GetParam();
  const std::string path = plctest::write_temp(std::string(c.name) + ".yaml", c.yaml);
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + path + " --cycles 10 -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  const std::string where = path + ":" + std::to_string(c.line) + ":";
  EXPECT_NE(r.output.find(where), std::string::npos)
      << "expected '" << where << "' in: " << r.output;
  EXPECT_NE(r.output.find(c.key), std::string::npos)
      << "expected key '" << c.key << "' in: " << r.output;
  EXPECT_NE(r.output.find(c.message), std::string::npos)
      << "expected '" << c.message << "' in: " << r.output;
  EXPECT_EQ(r.output.find("summary"), std::string::npos) << "nothing may start: " << r.output;
}

const Case kCases[] = {
    {"bad_yaml", replaced(kGood, "    period: 1ms", "    period: [1ms"), 5, "",
     "YAML syntax error"},
    {"unknown_key", replaced(kGood, "    period: 1ms", "    perod: 1ms"), 4, "perod",
     "unknown key"},
    {"missing_key", replaced(kGood, "    type: TankCycle\n", ""), 7, "type", "missing key"},
    {"bad_period", replaced(kGood, "period: 1ms", "period: fast"), 4, "period", "not a duration"},
    {"bad_address", replaced(kGood, "\"%IB0\"", "\"%IZ0\""), 16, "input",
     "invalid IEC address '%IZ0'"},
    {"bad_bit",
     replaced(kGood, "type: TankCycle", "type: TankCycle\n    bind: {level: \"%IX0.9\"}"), 9,
     "level", "out of range 0..7"},
    {"wrong_size_address",
     replaced(kGood, "type: TankCycle", "type: TankCycle\n    bind: {level: \"%ID0\"}"), 9,
     "Tank.level", "an INT needs a %IW"},
    {"address_outside_image", replaced(kGood, "cell: t\n", "cell: t\nimage: {inputs: 2}\n"), 17,
     "input", "needs 4 bytes from %IB0"},
    {"overlapping_addresses",
     std::string(kGood) +
         "  - name: echo2\n    plugin: sim\n    model: loopback\n    input: \"%IB2\"\n"
         "    output: \"%QB8\"\n",
     22, "input", "overlapping addresses: device 'echo2'"},
    {"unknown_plugin", replaced(kGood, "    type: sim", "    type: profibus9"), 11, "type",
     "unknown plugin type 'profibus9'"},
    {"undeclared_plugin", replaced(kGood, "    plugin: sim", "    plugin: bus"), 14, "plugin",
     "unknown plugin 'bus'"},
    {"unknown_program", replaced(kGood, "type: TankCycle", "type: NoSuchProgram"), 8, "type",
     "unknown program type 'NoSuchProgram'"},
    {"task_runs_unknown_program", replaced(kGood, "[Tank]", "[Tnk]"), 5, "Tnk",
     "unknown program 'Tnk'"},
    {"unknown_model", replaced(kGood, "model: loopback", "model: warp_drive"), 15, "model",
     "unknown device model 'warp_drive'"},
    {"unknown_model_param", replaced(kGood, "{size: 4}", "{size: 4, colour: red}"), 18, "colour",
     "unknown parameter 'colour'"},
    {"bad_model_param", replaced(kGood, "{size: 4}", "{size: huge}"), 18, "size",
     "expected an integer"},
    {"duplicate_task",
     replaced(kGood, "    programs: [Tank]\n",
              "    programs: [Tank]\n  - {name: main, period: 2ms, programs: []}\n"),
     6, "main", "duplicate task name"},
    {"unknown_bind",
     replaced(kGood, "type: TankCycle", "type: TankCycle\n    bind: {nope: \"%IX0.0\"}"), 9, "nope",
     "no located variable or device port"},
    {"bad_init", replaced(kGood, "type: TankCycle", "type: TankCycle\n    init: {high_level: abc}"),
     9, "high_level", "not an integer"},
    // Issue 10 point 5: internal state of a block is not settable.
    {"init_of_internal_state",
     replaced(kGood, "type: TankCycle", "type: TankCycle\n    init: {hold.running_: TRUE}"), 9,
     "hold.running_", "read-only: internal state of its function block"},
    // Issue 10 point 7: a value beyond its type's range names the range.
    {"init_out_of_range",
     replaced(kGood, "type: TankCycle", "type: TankCycle\n    init: {high_level: 40000}"), 9,
     "high_level", "out of range for INT (-32768 .. 32767)"},
    {"bad_safe_value", std::string(kGood) + "safe_values:\n  \"%IW0\": 1\n", 20, "safe_values",
     "not an output"},
    {"bad_clock", replaced(kGood, "cell: t\n", "cell: t\nclock: sometimes\n"), 2, "clock",
     "not virtual or realtime"},
    // Issue 10 point 8: every number in a config has a range (docs/config.md).
    // 100000d made --cycles overflow; 1e12 x period overflowed the watchdog
    // limit into a trip; the model values used to be taken as they came.
    {"period_too_long", replaced(kGood, "period: 1ms", "period: 100000d"), 4, "period",
     "out of range [T#1us, T#1d]"},
    {"period_of_a_day_and_a_microsecond", replaced(kGood, "period: 1ms", "period: 1d1us"), 4,
     "period", "out of range [T#1us, T#1d]"},
    {"period_below_a_microsecond", replaced(kGood, "period: 1ms", "period: 999ns"), 4, "period",
     "out of range [T#1us, T#1d]"},
    {"watchdog_too_large",
     replaced(kGood, "    period: 1ms\n", "    period: 1ms\n    watchdog: 1e12\n"), 5, "watchdog",
     "out of range [1, 1000]"},
    {"plugin_step_zero",
     replaced(kGood, "    type: sim\n", "    type: sim\n    params: {step: 0s}\n"), 12, "step",
     "out of range [T#10us, T#1s]"},
    {"model_time_negative", with_model("first_order", "{tau: -1s}"), 18, "tau",
     "out of range [T#1us, T#1d]"},
    {"model_number_out_of_range", with_model("first_order", "{gain: 1e300}"), 18, "gain",
     "out of range [-1000, 1000]"},
    {"pr5510_weight_beyond_dint", with_model("pr5510", "{full_scale: 30000000}"), 18, "full_scale",
     "weights are DINTs"},
    {"pr5510_negative_filter_time", with_model("pr5510", "{filter_time: -40ms}"), 18, "filter_time",
     "out of range [T#0s, T#1h]"},
    {"hiwin_telegram_beyond_range", with_model("hiwin_e1", "{telegram: 4294967407}"), 18,
     "telegram", "out of range [0, 65535]"},
    {"hiwin_position_beyond_range", with_model("hiwin_e1", "{initial_position: 1e300}"), 18,
     "initial_position", "out of range [-1e+18, 1e+18]"},
    {"nord_iparam_beyond_its_word", with_model("nord_profisafe", "{p803: 9999999999}"), 18, "p803",
     "out of range [-32768, 65535]"},
};

INSTANTIATE_TEST_SUITE_P(EachClass, ConfigErrors, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(ConfigErrorsMisc, MissingFileIsExitTwo) {
  const auto r = plctest::run_command(plctest::plcrun_path() + " /nonexistent/cell.yaml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cannot open"), std::string::npos) << r.output;
}

TEST(ConfigErrorsMisc, TheGoodConfigRuns) {
  const std::string path = plctest::write_temp("good.yaml", kGood);
  const auto r = plctest::run_command(plctest::plcrun_path() + " " + path + " --cycles 10 -q");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cycles 10"), std::string::npos) << r.output;
}

}  // namespace

// Issue 10 point 8: 1h and 1h1us share a 1us tick, 3.6e9 device steps per
// scan of the faster task: the virtual clock looked hung. plcrun now refuses
// it before anything runs, at the period that makes the tick that fine.
// (`timeout` bounds the old behaviour.)
TEST(ConfigErrorsMisc, PeriodsWithoutAUsefulCommonTickAreRefusedInVirtualTime) {
  const std::string path = plctest::write_temp(
      "tick.yaml",
      replaced(replaced(kGood, "period: 1ms", "period: 1h"), "    programs: [Tank]\n",
               "    programs: [Tank]\n  - {name: slow, period: 1h1us, programs: []}\n"));
  const auto r =
      plctest::run_command("timeout 60 " + plctest::plcrun_path() + " " + path + " --cycles 1 -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(path + ":6:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("choose periods with a larger common divisor"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("summary"), std::string::npos) << "nothing may start: " << r.output;
}
