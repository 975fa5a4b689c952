// Reading plcrun's CSV trace (and the debugger's `trace start FILE.csv`) in
// the cross-process cell tests: the header row names the columns, then one
// row per scan: time in ns, scan number, then the traced variables.
#pragma once

#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace plctest {

struct TraceRow {
  std::int64_t t_ns = 0;
  std::map<std::string, std::string> v;  // variable path -> value in IEC notation
};

// Every row of the trace at `path` (at most 10 million); none if it is missing.
inline std::vector<TraceRow> read_trace_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> head;
  std::vector<TraceRow> rows;
  for (int n = 0; n < 10'000'000 && std::getline(in, line); ++n) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (head.empty()) {
      head = cells;
      continue;
    }
    TraceRow r{std::stoll(cells.at(0)), {}};
    for (std::size_t i = 2; i < cells.size() && i < head.size(); ++i) r.v[head[i]] = cells[i];
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace plctest
