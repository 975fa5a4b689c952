// plcrun --checks FILE --results-json OUT: a scenario's pass/fail verdict,
// computed inside the run (scenario campaigns, tools/plcsweep).
//
// FILE is YAML; plcrun reads its `checks:` and `outputs:` keys and leaves
// every other key to its owner (a campaign file is a valid FILE, so errors
// name the campaign's own lines):
//
//   checks:
//     - name: in_tolerance          # unique
//       severity: error             # error (default: fails the scenario) | warning
//       always: "NOT Cell.dose.Done OR Cell.dose.InTol"
//       grace: 100ms                # always only: a violation must last longer
//     - name: filled_some
//       eventually: "Cell.containers >= 3"   # holds after at least one scan
//     - name: no_errors
//       at_end: "Cell.last_error = 0"        # on the values after the last scan
//   outputs: [Cell.containers, Cell.dose.LastNet]  # final, min and max
//
// Conditions are the debugger's (plc/debug/condition.hpp), compiled once;
// after every scan of the task that owns a condition's first variable (every
// scan when it reads addresses only) each always/eventually condition is
// evaluated: no allocation, a few dozen postfix instructions. This is the
// cheaper of the two ways to check a run: a debugger session with
// breakpoints would stop the cell on a violation and run it scan by scan
// through the session layer, where this observer only reads variables.
//
// Scans are numbered as the debugger numbers them (scans of any task so
// far), so a failure at scan N is `goto N` in `plcrun --replay ... --debug`.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plc/cell_config.hpp"
#include "plc/debug/condition.hpp"
#include "plc/runtime.hpp"

namespace plc {

enum class CheckKind { Always, AtEnd, Eventually };
enum class CheckSeverity { Error, Warning };

struct CheckSpec {
  Item<std::string> name;
  CheckKind kind = CheckKind::Always;
  CheckSeverity severity = CheckSeverity::Error;
  Item<std::string> condition;
  TIME grace{0};
};

struct ChecksFile {
  std::string file;
  std::vector<CheckSpec> checks;
  std::vector<Item<std::string>> outputs;
};

// Throws ConfigError (file:line:column) for bad YAML, a missing or unknown
// key inside `checks:` items, duplicate names, a bad severity or grace.
ChecksFile load_checks_file(const std::string& path);
ChecksFile parse_checks_file(const std::string& yaml_text, const std::string& file_name);

class ScenarioChecks {
 public:
  // Compiles every condition and output against `rt` and installs the scan
  // observer. Throws ConfigError at the condition's or output's position
  // when it does not compile (unknown variable, syntax).
  ScenarioChecks(Runtime& rt, ChecksFile spec);

  // After the run: evaluates at_end checks and the outputs' final values.
  void finish();
  // True when no check of severity error failed (valid after finish()).
  [[nodiscard]] bool passed() const;
  // The verdict as one JSON object (valid after finish()). Everything but
  // the "timing" member is a function of the config alone (virtual time),
  // so two runs of one scenario give the same bytes there.
  [[nodiscard]] std::string json(const std::string& stop_reason) const;
  // One line per failed check, for the terminal.
  [[nodiscard]] std::string failures_text() const;

 private:
  struct Check {
    Check(CheckSpec s, debug::Condition c) : spec(std::move(s)), cond(std::move(c)) {}
    CheckSpec spec;
    debug::Condition cond;
    bool failed = false;
    bool held = false;  // eventually: held after some scan
    std::uint64_t first_fail_scan = 0;
    TIME first_fail_time{0};
    std::uint64_t violating_scans = 0;  // always: scans where it did not hold
    std::optional<TIME> violation_since;
  };
  struct Output {
    std::string path;
    const VarInfo* var = nullptr;
    double min = 0, max = 0;
    bool seen = false;
    std::string final_text;
    double final_value = 0;
  };
  void after_scan(const TaskRuntime& t, const ScanContext& ctx);

  Runtime& rt_;
  std::string file_;
  std::vector<Check> checks_;
  std::vector<Output> outputs_;
  std::uint64_t scans_ = 0;
  TIME last_time_{0};
  std::uint64_t state_digest_ = 0;
};

}  // namespace plc
