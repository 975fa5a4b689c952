// What every benchmark executable shares: Google Benchmark's table goes to
// stderr, and the executable prints its figures on stdout as `name: value
// unit` lines (scripts/bench parses them) from the times collected here.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace plc::bench {

class Collector : public benchmark::ConsoleReporter {
 public:
  // No colour codes on the table (it may go to a log).
  Collector() : ConsoleReporter(OO_Tabular) {
    SetOutputStream(&std::cerr);
    SetErrorStream(&std::cerr);
  }

  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.error_occurred || r.run_type != Run::RT_Iteration) continue;
      if (!cpu_.count(r.benchmark_name())) order_.push_back(r.benchmark_name());
      cpu_[r.benchmark_name()] = r.GetAdjustedCPUTime();
      wall_[r.benchmark_name()] = r.GetAdjustedRealTime();
    }
  }

  // The adjusted CPU or wall time per iteration (in the benchmark's time
  // unit, ns unless it sets another) of the first benchmark whose name
  // starts with `prefix`; 0 when none ran (filtered out, or it failed).
  [[nodiscard]] double cpu(std::string_view prefix) const { return find(cpu_, prefix); }
  [[nodiscard]] double wall(std::string_view prefix) const { return find(wall_, prefix); }

  // One `name: N ns` line per benchmark, wall time, in the order they ran.
  void print_wall_lines() const {
    for (const std::string& n : order_)
      std::printf("%s: %lld ns\n", n.c_str(), static_cast<long long>(wall_.at(n) + 0.5));
  }

 private:
  static double find(const std::map<std::string, double>& m, std::string_view prefix) {
    for (const auto& [name, v] : m)
      if (std::string_view(name).substr(0, prefix.size()) == prefix) return v;
    return 0.0;
  }
  std::map<std::string, double> cpu_, wall_;
  std::vector<std::string> order_;
};

// Initialize, refuse unknown arguments, run every selected benchmark into
// `c`. Returns false (after a message) on a bad argument.
inline bool run_benchmarks(int& argc, char** argv, Collector& c) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return false;
  benchmark::RunSpecifiedBenchmarks(&c);
  benchmark::Shutdown();
  return true;
}

}  // namespace plc::bench
