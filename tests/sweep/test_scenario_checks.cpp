// plcrun --checks (runtime/plcrun/checks.hpp): always / at_end / eventually
// with grace and severity, located errors, the scan numbering the debugger
// uses; and the sim plugin's link fault switch (link_down_at/_for,
// docs/config.md) the campaigns' fault schedules use.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "checks.hpp"
#include "plc/cell_config.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/runtime.hpp"
#include "runtime/test_helpers.hpp"

using namespace plc;

namespace {

std::string filling_cell() {
  return plctest::read_file(plctest::source_path("programs/filling_cell/cell.yaml"));
}

// The filling cell with `extra` appended to the safety device's params.
std::string filling_cell_with_safety_params(const std::string& extra) {
  std::string cell = filling_cell();
  const std::string key = "      p840: 0";
  const auto at = cell.find(key);
  EXPECT_NE(at, std::string::npos);
  cell.insert(cell.find('\n', at) + 1, extra);
  return cell;
}

struct CheckedRun {
  std::unique_ptr<Runtime> rt;
  std::unique_ptr<ScenarioChecks> checks;
  std::string json;
};

CheckedRun run(const std::string& cell, const std::string& checks_yaml, TIME span) {
  CheckedRun r;
  r.rt = std::make_unique<Runtime>(parse_cell_config(cell, "cell.yaml"));
  r.checks = std::make_unique<ScenarioChecks>(*r.rt, parse_checks_file(checks_yaml, "c.yaml"));
  r.rt->run(io::ClockMode::Virtual, span);
  r.checks->finish();
  r.json = r.checks->json("");
  return r;
}

bool has(const std::string& s, const std::string& what) {
  return s.find(what) != std::string::npos;
}

// The value of `"key":` in the object of check `name` (a number).
std::string field(const std::string& json, const std::string& name, const std::string& key) {
  const auto at = json.find("{\"name\":\"" + name + "\"");
  if (at == std::string::npos) return "";
  const auto end = json.find('}', at);
  const auto k = json.find("\"" + key + "\":", at);
  if (k == std::string::npos || k > end) return "";
  const auto v = k + key.size() + 3;
  return json.substr(v, json.find_first_of(",}", v) - v);
}

std::string error_of(const std::string& yaml) {
  try {
    parse_checks_file(yaml, "c.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ScenarioChecks, FileErrorsNameLineAndColumn) {
  EXPECT_EQ(error_of("checks:\n  - name: a\n    always: \"TRUE\"\n    colour: red\n"),
            "c.yaml:4:5: unknown key 'colour' in a check (expected one of: always, at_end, "
            "eventually, grace, name, severity)");
  EXPECT_EQ(error_of("checks:\n  - name: a\n    severity: fatal\n    always: \"TRUE\"\n"),
            "c.yaml:3:15: key 'severity': 'fatal' is not error or warning");
  EXPECT_EQ(error_of("checks:\n  - name: a\n    always: \"TRUE\"\n    at_end: \"TRUE\"\n"),
            "c.yaml:2:5: check 'a' needs exactly one of always:, at_end:, eventually:");
  EXPECT_EQ(error_of("checks:\n  - {name: a, at_end: \"TRUE\", grace: 1s}\n"),
            "c.yaml:2:38: key 'grace' applies to always: checks only");
  EXPECT_EQ(error_of("checks:\n  - {name: a, at_end: \"TRUE\"}\n  - {name: a, at_end: \"1\"}\n"),
            "c.yaml:3:12: duplicate check name 'a'");
  EXPECT_EQ(error_of("campaign: x\n"), "c.yaml:1:1: missing key 'checks' (a list of checks)");
  // Keys other than checks: and outputs: belong to the campaign file.
  EXPECT_EQ(error_of("base: cell.yaml\nchecks: []\n"), "");
}

TEST(ScenarioChecks, AnUnknownVariableIsRefusedAtTheConditionsPosition) {
  Runtime rt(parse_cell_config(filling_cell(), "cell.yaml"));
  try {
    ScenarioChecks c(rt, parse_checks_file(
                             "checks:\n  - name: a\n    always: \"Cell.nothing = 0\"\n", "c.yaml"));
    FAIL() << "compiled";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(has(e.what(), "c.yaml:3:13: check 'a': ")) << e.what();
    EXPECT_TRUE(has(e.what(), "Cell.nothing")) << e.what();
  }
}

TEST(ScenarioChecks, AlwaysFailsAtTheScanTheDebuggerNumbersTheSame) {
  // A 1 ms task: scan N ends at t = (N-1) ms. The check fails after the
  // scan that counts the second container; the debugger's goto N puts a
  // session after that same scan.
  const CheckedRun r =
      run(filling_cell(),
          "checks:\n  - name: fewer_than_two\n    always: \"Cell.containers < 2\"\n"
          "  - name: never_error\n    always: \"Cell.last_error = 0\"\n",
          std::chrono::seconds(60));
  EXPECT_FALSE(r.checks->passed());
  EXPECT_TRUE(has(r.json, "\"passed\":false")) << r.json;
  EXPECT_EQ(field(r.json, "never_error", "passed"), "true") << r.json;
  const std::string scan = field(r.json, "fewer_than_two", "first_fail_scan");
  ASSERT_FALSE(scan.empty()) << r.json;
  const std::uint64_t n = std::stoull(scan);
  EXPECT_NEAR(std::stod(field(r.json, "fewer_than_two", "first_fail_time_s")), double(n - 1) / 1000,
              1e-9);

  static CellConfig cfg;
  cfg = parse_cell_config(filling_cell(), "cell.yaml");
  debug::Debugger::Options o;
  o.span = std::chrono::seconds(60);
  debug::Debugger d([] { return std::make_unique<Runtime>(cfg); }, o);
  d.execute("goto " + std::to_string(n - 1));
  EXPECT_TRUE(has(d.execute("print Cell.containers"), "Cell.containers = 1")) << n;
  d.execute("goto " + std::to_string(n));
  EXPECT_TRUE(has(d.execute("print Cell.containers"), "Cell.containers = 2")) << n;
}

TEST(ScenarioChecks, GraceCountsAViolationOnlyOnceItHasLastedThatLong) {
  // Indexing one container takes about 250 ms (pitch 50000 CU at 200000
  // CU/s): NOT index.Busy is violated that long, every time.
  const CheckedRun r =
      run(filling_cell(),
          "checks:\n"
          "  - {name: no_grace, always: \"NOT Cell.index.Busy\"}\n"
          "  - {name: grace_100ms, always: \"NOT Cell.index.Busy\", grace: 100ms}\n"
          "  - {name: grace_2s, always: \"NOT Cell.index.Busy\", grace: 2s}\n",
          std::chrono::seconds(30));
  const double t0 = std::stod(field(r.json, "no_grace", "first_fail_time_s"));
  const double t1 = std::stod(field(r.json, "grace_100ms", "first_fail_time_s"));
  EXPECT_NEAR(t1 - t0, 0.100, 1e-9) << r.json;
  EXPECT_EQ(field(r.json, "grace_2s", "passed"), "true") << r.json;
  // Both count every violating scan, grace or not.
  EXPECT_EQ(field(r.json, "no_grace", "violating_scans"),
            field(r.json, "grace_2s", "violating_scans"));
}

TEST(ScenarioChecks, EventuallyAtEndSeverityAndOutputs) {
  const CheckedRun r =
      run(filling_cell(),
          "checks:\n"
          "  - {name: three, eventually: \"Cell.containers >= 3\"}\n"
          "  - {name: thousand, eventually: \"Cell.containers >= 1000\", "
          "severity: warning}\n"
          "  - {name: end_ok, at_end: \"Cell.last_error = 0\"}\n"
          "  - {name: end_many, at_end: \"Cell.containers > 1000\", severity: warning}\n"
          "outputs: [Cell.containers, Cell.dose.LastNet]\n",
          std::chrono::seconds(60));
  EXPECT_TRUE(r.checks->passed()) << "warnings do not fail a scenario: " << r.json;
  EXPECT_EQ(field(r.json, "three", "passed"), "true");
  EXPECT_EQ(field(r.json, "thousand", "passed"), "false");
  EXPECT_EQ(field(r.json, "end_ok", "passed"), "true");
  EXPECT_EQ(field(r.json, "end_many", "passed"), "false");
  EXPECT_EQ(field(r.json, "end_many", "first_fail_scan"), "60000") << r.json;
  EXPECT_TRUE(has(r.json, "\"Cell.containers\":{\"final\":")) << r.json;
  EXPECT_TRUE(has(r.json, "\"min\":0,")) << r.json;
  EXPECT_TRUE(has(r.checks->failures_text(), "check warning: thousand (eventually")) << r.json;
}

TEST(ScenarioChecks, TwoRunsGiveTheSameVerdictAndStateDigest) {
  const std::string checks =
      "checks:\n  - {name: a, always: \"Cell.dose.OutTolCount = 0\"}\noutputs: "
      "[Cell.dose.LastNet]\n";
  const CheckedRun a = run(filling_cell(), checks, std::chrono::seconds(20));
  const CheckedRun b = run(filling_cell(), checks, std::chrono::seconds(20));
  auto strip = [](const std::string& j) { return j.substr(0, j.find(",\"timing\"")); };
  EXPECT_EQ(strip(a.json), strip(b.json));
  // Another noise seed: another state.
  std::string cell = filling_cell();
  cell.replace(cell.find("seed: 7"), 7, "seed: 8");
  const CheckedRun c = run(cell, checks, std::chrono::seconds(20));
  EXPECT_NE(strip(a.json), strip(c.json));
}

// docs/config.md, sim plugin: link_down_at / link_down_for. The F-host's
// watchdog is F_WD_Time = 100 ms (filling_station.hpp): a cut of 50 ms is
// ridden through, one of 300 ms passivates it; never before the cut.
TEST(SimLinkFault, ACutLongerThanTheProfisafeWatchdogPassivatesTheFHost) {
  auto cell = [](const char* dur) {
    return filling_cell_with_safety_params(
        "      link_down_at: 5s\n      link_down_for: " + std::string(dur) + "\n");
  };
  const std::string good = "checks:\n  - {name: ok, always: \"NOT Cell.guard.QBAD\"}\n";
  // The F-host starts passivated until its first good exchanges: those
  // scans are the violations of a cell without a cut.
  const CheckedRun nocut = run(filling_cell(), good, std::chrono::seconds(10));
  const std::uint64_t startup = std::stoull(field(nocut.json, "ok", "violating_scans"));
  EXPECT_GT(startup, 0u) << nocut.json;
  const CheckedRun before = run(cell("300ms"), good, std::chrono::milliseconds(4999));
  EXPECT_EQ(std::stoull(field(before.json, "ok", "violating_scans")), startup) << before.json;
  const CheckedRun shortcut = run(cell("50ms"), good, std::chrono::seconds(10));
  EXPECT_EQ(std::stoull(field(shortcut.json, "ok", "violating_scans")), startup)
      << "a 50 ms cut is inside the 100 ms watchdog: " << shortcut.json;
  const CheckedRun longcut = run(cell("300ms"), good, std::chrono::seconds(10));
  EXPECT_GT(std::stoull(field(longcut.json, "ok", "violating_scans")), startup + 100)
      << longcut.json;
}

TEST(SimLinkFault, LinkDownForWithoutLinkDownAtIsAConfigError) {
  const auto cell = filling_cell_with_safety_params("      link_down_for: 50ms\n");
  try {
    Runtime rt(parse_cell_config(cell, "cell.yaml"));
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(has(e.what(), "link_down_for needs link_down_at")) << e.what();
  }
}

TEST(PlcrunChecks, ExitCodeThreeAndTheResultsJson) {
  const std::string checks = plctest::write_temp(
      "sweep_checks.yaml", "checks:\n  - {name: few, always: \"Cell.containers < 2\"}\n");
  const std::string out = plctest::temp_path("sweep_results.json");
  const std::string cell = plctest::source_path("programs/filling_cell/cell.yaml");
  auto r = plctest::run_command(plctest::plcrun_path() + " " + cell +
                                " --quiet --for 60s --checks " + checks + " --results-json " + out);
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_TRUE(has(r.output, "check FAILED: few (always Cell.containers < 2) at scan ")) << r.output;
  EXPECT_TRUE(has(plctest::read_file(out), "\"name\":\"few\"")) << plctest::read_file(out);
  r = plctest::run_command(plctest::plcrun_path() + " " + cell + " --quiet --for 1s --checks " +
                           checks);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = plctest::run_command(plctest::plcrun_path() + " " + cell + " --results-json " + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = plctest::run_command(plctest::plcrun_path() + " " + cell + " --debug --checks " + checks +
                           " </dev/null");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}
