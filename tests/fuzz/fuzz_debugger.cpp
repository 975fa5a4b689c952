// Fuzz target: the debugger's command line (Debugger::execute), one command
// per input line, on the filling cell in virtual time; freeze points read
// their commands from the following lines. Every line gets an answer, never
// a crash. The session ends after 1 s of virtual time (so `continue` and
// `goto` are bounded) and files are written only where the target says:
// `record FILE` and `trace start FILE` go to a temporary file.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_cell.hpp"
#include "fuzz_input.hpp"
#include "plc/debug/debugger.hpp"

namespace {

constexpr int kMaxCommands = 32;

std::string temp_file(const char* ext) {
  return "/tmp/plc_fuzz_debugger_" + std::to_string(::getpid()) + ext;
}

// The line with any file name replaced by the temporary file (words split
// as the debugger splits them: at blanks and commas).
std::string confine_files(std::string_view line) {
  std::vector<std::string_view> w;
  for (std::size_t i = 0; i < line.size();) {
    const std::size_t b = line.find_first_not_of(" \t\r\v\f,", i);
    if (b == std::string_view::npos) break;
    const std::size_t e = std::min(line.find_first_of(" \t\r\v\f,", b), line.size());
    w.push_back(line.substr(b, e - b));
    i = e;
  }
  if (w.size() >= 2 && w[0] == "record" && w[1] != "stop") return "record " + temp_file(".rec");
  if (w.size() >= 3 && w[0] == "trace" && w[1] == "start")
    return "trace start " + temp_file(w[2].ends_with(".vcd") ? ".vcd" : ".csv");
  return std::string(line);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  plc::fuzz::FuzzInput in(data, size);
  plc::debug::Debugger::Options opt;
  opt.span = std::chrono::seconds(1);
  plc::debug::Debugger dbg([] { return std::make_unique<plc::Runtime>(plc::fuzz::filling_cell()); },
                           opt);
  int commands = 0;
  dbg.set_io(
      [&](const std::string&) -> std::optional<std::string> {
        if (in.empty() || ++commands > kMaxCommands) return std::nullopt;
        return confine_files(in.line());
      },
      [](const std::string&) {});
  while (!in.empty() && !dbg.quit_requested() && ++commands <= kMaxCommands)
    (void)dbg.execute(confine_files(in.line()));
  return 0;
}
