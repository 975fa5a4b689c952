// The body of POST /api/command (hmi-bridge/README.md "Web HMI"): the verb
// on the first line, one argument per line after it, as plcctl takes them
// ("write\nMain.setpoint\n42"). Lines, not JSON: the only text the web
// server parses besides HTTP itself, bounded and checked byte by byte
// (tests/fuzz/fuzz_web_command.cpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace plc::hmi::web {

inline constexpr std::size_t kMaxCommandBody = 4096;
inline constexpr std::size_t kMaxCommandArgs = 8;
inline constexpr std::size_t kMaxCommandLine = 512;

struct CommandBody {
  std::string verb;
  std::vector<std::string> args;
};

// The verbs a browser may send: read, write, force, unforce, pause, step,
// continue (to the bridge, as plcctl's), and ack ID|all (an alarm event,
// kept by the web server). `error` says what is wrong otherwise. A trailing newline and
// "\r\n" line ends are accepted; control characters (NUL among them) are
// not.
bool parse_command_body(std::string_view body, CommandBody& out, std::string& error);
// Whether `verb` is an operator's action (refused in read-only mode):
// everything but read.
bool changes_cell(const std::string& verb);

}  // namespace plc::hmi::web
