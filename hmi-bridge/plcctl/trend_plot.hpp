// `plcctl trend`: samples of some variables over time, written as CSV (a
// header row, then time in seconds and one column per variable: any
// spreadsheet or gnuplot plots it directly) or drawn into a PNG with PLplot,
// one panel per type class over a common time axis (trend_layout.hpp).
#pragma once

#include <string>
#include <vector>

namespace plc::hmi {

struct Trend {
  std::vector<std::string> names;
  std::vector<std::string> types;          // IEC type names, as var_desc_t gives them
  std::vector<double> t;                   // seconds of PLC time
  std::vector<std::vector<double>> value;  // [variable][sample]
};

// "" on success, else why not.
std::string write_trend_csv(const Trend& tr, const std::string& file);
std::string write_trend_png(const Trend& tr, const std::string& file, const std::string& title);

}  // namespace plc::hmi
