// plcrun's debugger front ends: an interactive console with line editing
// and history (libedit), and command files (--commands) for tests and
// scripts. Both drive plc::debug::Debugger, the command layer.
#pragma once

#include <string>

#include "plc/debug/debugger.hpp"

namespace plc {

// Runs the commands of `file` (echoing each, then its output); then, if
// `interactive`, continues at the console. Returns when the session quits.
// Returns false if the file cannot be read.
bool run_debug_session(debug::Debugger& dbg, const std::string& commands_file, bool interactive);

}  // namespace plc
