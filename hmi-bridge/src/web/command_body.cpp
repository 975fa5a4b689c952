#include "plc/hmi/web/command_body.hpp"

#include <algorithm>
#include <array>

namespace plc::hmi::web {

namespace {

constexpr std::array<std::string_view, 8> kVerbs = {"read",  "write", "force",    "unforce",
                                                    "pause", "step",  "continue", "ack"};

}  // namespace

bool parse_command_body(std::string_view body, CommandBody& out, std::string& error) {
  out = {};
  if (body.size() > kMaxCommandBody) {
    error = "command longer than " + std::to_string(kMaxCommandBody) + " bytes";
    return false;
  }
  if (!body.empty() && body.back() == '\n') body.remove_suffix(1);
  if (!body.empty() && body.back() == '\r') body.remove_suffix(1);
  std::vector<std::string> lines;
  for (std::size_t from = 0;;) {
    auto end = body.find('\n', from);
    std::string_view line = body.substr(from, end == std::string_view::npos ? end : end - from);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.size() > kMaxCommandLine) {
      error = "a line longer than " + std::to_string(kMaxCommandLine) + " bytes";
      return false;
    }
    for (const char c : line)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
        error = "a control character in the command";
        return false;
      }
    if (lines.size() == kMaxCommandArgs + 1) {
      error = "more than " + std::to_string(kMaxCommandArgs) + " arguments";
      return false;
    }
    lines.emplace_back(line);
    if (end == std::string_view::npos) break;
    from = end + 1;
  }
  if (lines.empty() || lines[0].empty()) {
    error = "no verb";
    return false;
  }
  if (std::find(kVerbs.begin(), kVerbs.end(), lines[0]) == kVerbs.end()) {
    error =
        "unknown verb '" + lines[0] + "' (read, write, force, unforce, pause, step, continue, ack)";
    return false;
  }
  out.verb = lines[0];
  out.args.assign(lines.begin() + 1, lines.end());
  return true;
}

bool changes_cell(const std::string& verb) { return verb != "read"; }

}  // namespace plc::hmi::web
