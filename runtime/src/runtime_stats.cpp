#include <cmath>
#include <sstream>

#include "plc/runtime.hpp"

namespace plc {
namespace {

void histogram_json(std::ostringstream& o, const Histogram& h) {
  o << "{\"count\": " << h.count() << ", \"min\": " << h.min()
    << ", \"avg\": " << std::llround(h.mean()) << ", \"p50\": " << h.percentile(0.50)
    << ", \"p99\": " << h.percentile(0.99) << ", \"p999\": " << h.percentile(0.999)
    << ", \"max\": " << h.max() << "}";
}

std::string escaped(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o;
}

}  // namespace

std::string Runtime::stats_json() const {
  std::ostringstream o;
  o << "{\n  \"cell\": \"" << escaped(cell_name_) << "\",\n  \"clock\": \""
    << (mode_ == io::ClockMode::Virtual ? "virtual" : "realtime")
    << "\",\n  \"time_ns\": " << now_.count() << ",\n  \"wall_s\": " << wall_seconds_
    << ",\n  \"tasks\": [";
  for (std::size_t i = 0; i < tasks_.size(); ++i) {
    const TaskRuntime& t = *tasks_[i];
    const TaskStats st = t.stats.snapshot();
    o << (i ? "," : "") << "\n    {\"name\": \"" << escaped(t.name)
      << "\", \"period_ns\": " << t.period.count() << ", \"priority\": " << t.priority
      << ", \"scans\": " << st.scans << ", \"overruns\": " << st.overruns
      << ", \"skipped\": " << st.skipped
      << ", \"watchdog_tripped\": " << (st.watchdog_tripped ? "true" : "false")
      << ", \"stop_reason\": \"" << escaped(st.stop_reason) << "\",\n     \"scan_ns\": ";
    histogram_json(o, st.scan_ns);
    o << ",\n     \"latency_ns\": ";
    histogram_json(o, st.latency_ns);
    o << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

}  // namespace plc
