#include "debug_console.hpp"

#include <editline/readline.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <iostream>
#include <optional>

namespace plc {
namespace {

std::string history_file() {
  const char* home = std::getenv("HOME");
  return std::string(home ? home : ".") + "/.plcrun_history";
}

void print(const std::string& s) {
  std::fwrite(s.data(), 1, s.size(), stdout);
  std::fflush(stdout);
}

}  // namespace

bool run_debug_session(debug::Debugger& dbg, const std::string& commands_file, bool interactive) {
  std::deque<std::string> scripted;
  if (!commands_file.empty()) {
    std::ifstream in(commands_file);
    if (!in) return false;
    for (std::string line; std::getline(in, line);) scripted.push_back(line);
  }
  const bool tty = isatty(STDIN_FILENO) != 0;
  if (interactive && tty) {
    using_history();
    read_history(history_file().c_str());
  }
  // One reader for the top level and for freeze points: script lines first,
  // then the console (or plain stdin when it is not a terminal).
  auto reader = [&](const std::string& prompt) -> std::optional<std::string> {
    if (dbg.end_requested()) return std::nullopt;  // SIGTERM: no more commands
    if (!scripted.empty()) {
      std::string line = scripted.front();
      scripted.pop_front();
      print(prompt + line + "\n");
      return line;
    }
    if (!interactive) return std::nullopt;
    if (tty) {
      char* raw = readline(prompt.c_str());
      if (!raw) return std::nullopt;
      std::string line(raw);
      std::free(raw);
      if (!line.empty()) add_history(line.c_str());
      return line;
    }
    print(prompt);
    std::string line;
    if (!std::getline(std::cin, line)) return std::nullopt;
    return line;
  };
  dbg.set_io(reader, print);
  if (interactive)
    print("plcrun debugger: 'help' lists the commands, Ctrl-C interrupts a run, 'quit' leaves\n");
  while (!dbg.quit_requested() && !dbg.end_requested()) {
    auto line = reader(dbg.prompt());
    if (!line) break;
    print(dbg.execute(*line));
  }
  if (interactive && tty) write_history(history_file().c_str());
  return true;
}

}  // namespace plc
