// Shared helpers for the runtime tests: build a runtime from YAML text, run
// plcrun as a child process.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include "plc/cell_config.hpp"
#include "plc/runtime.hpp"
#include "plc_test_paths.hpp"

namespace plctest {

inline std::unique_ptr<plc::Runtime> make_runtime(const std::string& yaml) {
  return std::make_unique<plc::Runtime>(plc::parse_cell_config(yaml, "test.yaml"));
}

inline std::string plcrun_path() { return bin_dir() + "/plcrun"; }

inline std::string temp_path(const std::string& name) {
  const char* t = std::getenv("TMPDIR");
  return std::string(t ? t : "/tmp") + "/plc_test_" + std::to_string(::getpid()) + "_" + name;
}

inline std::string write_temp(const std::string& name, const std::string& text) {
  const std::string p = temp_path(name);
  std::ofstream(p) << text;
  return p;
}

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

inline RunResult run_command(const std::string& cmd) {
  RunResult r;
  std::FILE* f = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!f) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) r.output.append(buf, n);
  const int status = ::pclose(f);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// s with every `from` replaced by `to` (a config's port or path made the test's own).
inline std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (auto p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

// The value of `var` in plcrun's `--print-vars` output ("VAR = VALUE"
// lines); "?" when it is not there.
inline std::string printed_value(const std::string& out, const std::string& var) {
  const auto at = out.find(var + " = ");
  if (at == std::string::npos) return "?";
  const auto from = at + var.size() + 3;
  return out.substr(from, out.find('\n', from) - from);
}

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The demo cell (programs/demo/cell.yaml) with both tasks' watchdogs off,
// written to the temporary file `name`: for real-time tests that assert
// nothing about timing, where a loaded machine that stalls one scan for
// more than 10 periods must not stop a task (plcrun then exits 1, and a
// session's forces stop taking effect). "" when the demo no longer has
// the lines this edits.
inline std::string demo_without_watchdogs(const std::string& name) {
  std::string cell = read_file(source_path("programs/demo/cell.yaml"));
  const auto wd = cell.find("    watchdog: 10 ");
  const auto slow = cell.find("    priority: 5\n");
  if (wd == std::string::npos || slow == std::string::npos) return "";
  cell.insert(slow + 16, "    watchdog: 0\n");  // after wd: wd's offset holds
  cell.replace(wd, 17, "    watchdog: 0  ");
  return write_temp(name, cell);
}

}  // namespace plctest
