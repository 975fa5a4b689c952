// plcrun's command line, callable in-process (main.cpp and tests).
#pragma once

namespace plc {
// Exit codes: 0 ok, 1 runtime failure (a plugin failed to start, a task was
// stopped by its watchdog or a fault), 2 bad command line or bad config,
// 3 a check of severity error failed (--checks).
int plcrun_main(int argc, char** argv);
}  // namespace plc
