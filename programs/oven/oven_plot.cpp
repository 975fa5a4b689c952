// oven_plot: draws a plcrun CSV trace (plcrun --trace FILE.csv) into a PNG
// with plcctl's trend layout (hmi-bridge/plcctl/trend_layout.hpp: one panel
// per type class over a common time axis). Used for the oven figure in the
// README:
//
//   build/bin/plcrun programs/oven/cell.yaml --for 1h --trace oven.csv
//     --trace-vars Oven.temperature,Oven.pid.EffectiveSetpoint,Oven.pid.Output,Oven.tune.Phase
//   build/bin/oven_plot oven.csv oven.png "oven: step test, then PID"
//
// A column's type comes from its first value: TRUE/FALSE is a BOOL, a
// number with a point or an exponent a REAL, other numbers an integer
// (DINT); anything else (TIME, STRING) is left out. Exit 0, or 2 with a
// message.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "trend_plot.hpp"

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
  return cells;
}

std::string type_of(const std::string& v) {
  if (v == "TRUE" || v == "FALSE") return "BOOL";
  if (v.empty()) return "";
  bool digits = true, real = false;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const char c = v[i];
    if (c == '.' || c == 'e' || c == 'E') {
      real = true;
    } else if (!((c >= '0' && c <= '9') ||
                 ((c == '-' || c == '+') && (i == 0 || v[i - 1] == 'e' || v[i - 1] == 'E')))) {
      digits = false;
    }
  }
  if (v == "nan" || v == "-nan" || v == "inf" || v == "-inf") return "REAL";
  if (!digits) return "";
  return real ? "REAL" : "DINT";
}

double value_of(const std::string& v) {
  if (v == "TRUE") return 1;
  if (v == "FALSE") return 0;
  try {
    return std::stod(v);
  } catch (...) {
    return NAN;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: oven_plot TRACE.csv OUT.png [TITLE]\n");
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::fprintf(stderr, "oven_plot: cannot read '%s'\n", argv[1]);
    return 2;
  }
  std::string line;
  if (!std::getline(in, line)) {
    std::fprintf(stderr, "oven_plot: '%s' is empty\n", argv[1]);
    return 2;
  }
  const std::vector<std::string> head = split(line);
  if (head.size() < 3 || head[0] != "time_ns" || head[1] != "cycle") {
    std::fprintf(stderr, "oven_plot: '%s' is not a plcrun CSV trace (time_ns,cycle,...)\n",
                 argv[1]);
    return 2;
  }
  plc::hmi::Trend tr;
  std::vector<int> column;  // trace column -> trend series, -1: left out
  bool typed = false;
  for (std::size_t n = 0; n < 10'000'000 && std::getline(in, line); ++n) {
    const std::vector<std::string> cells = split(line);
    if (cells.size() != head.size()) continue;
    if (!typed) {
      for (std::size_t c = 2; c < head.size(); ++c) {
        const std::string t = type_of(cells[c]);
        column.push_back(t.empty() ? -1 : static_cast<int>(tr.names.size()));
        if (!t.empty()) {
          tr.names.push_back(head[c]);
          tr.types.push_back(t);
          tr.value.emplace_back();
        }
      }
      typed = true;
    }
    tr.t.push_back(value_of(cells[0]) * 1e-9);
    for (std::size_t c = 2; c < head.size(); ++c)
      if (column[c - 2] >= 0)
        tr.value[static_cast<std::size_t>(column[c - 2])].push_back(value_of(cells[c]));
  }
  const std::string err = plc::hmi::write_trend_png(tr, argv[2], argc == 4 ? argv[3] : argv[1]);
  if (!err.empty()) {
    std::fprintf(stderr, "oven_plot: %s\n", err.c_str());
    return 2;
  }
  return 0;
}
