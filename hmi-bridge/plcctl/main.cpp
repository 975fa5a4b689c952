// plcctl: watch and operate a running cell through its HMI bridge (LCM over
// our own transport, plc/hmi/transport.hpp).
// Exit codes as plcrun's: 0 done, 1 refused or no answer, 2 bad usage. A
// watch, log or trend ended by Ctrl-C (or --for/--count) ends normally.
#include <unistd.h>

#include <boost/program_options.hpp>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <map>

#include "client.hpp"
#include "plc/hmi/bridge.hpp"
#include "plc/iec_literal.hpp"
#include "softplc_hmi/alarm_t.hpp"
#include "softplc_hmi/diagnostics_t.hpp"
#include "softplc_hmi/stats_t.hpp"
#include "softplc_hmi/trace_sample_t.hpp"
#include "softplc_hmi/values_t.hpp"
#include "trend_plot.hpp"

namespace po = boost::program_options;
using namespace plc;
using namespace plc::hmi;

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

const char* kUsage =
    "Usage: plcctl [options] COMMAND [ARGS]\n\n"
    "Commands:\n"
    "  list [PATTERN]            variables: path, type, address, w (writable) f (forceable)\n"
    "  watch PATTERN...          live values (in place on a terminal, lines when piped)\n"
    "  read NAME...              values now (IEC notation)\n"
    "  write NAME VALUE          once, at the start of the next scan\n"
    "  force NAME VALUE          every scan until unforce\n"
    "  unforce NAME|all [restore]\n"
    "  pause | step [N] | continue\n"
    "  break CONDITION | delete ID|all\n"
    "  stats | devices | alarms  the bridge's 1 Hz messages (alarms --for/--count: then\n"
    "                            each device lost/back as it happens)\n"
    "  log FILE                  record the bridge's channels (lcm-logger format)\n"
    "  trend PATTERN... (--png FILE | --csv FILE)  sample and plot\n";

// Time-boxed commands (watch, log, trend) run until --for, --count or Ctrl-C.
struct Span {
  std::chrono::steady_clock::time_point end = std::chrono::steady_clock::time_point::max();
  std::uint64_t count = 0;  // 0: no limit
  bool over(std::uint64_t seen) const {
    return g_stop || (count && seen >= count) || std::chrono::steady_clock::now() >= end;
  }
};

bool matches_any(const std::vector<std::string>& patterns, const softplc_hmi::var_desc_t& v) {
  for (const auto& p : patterns)
    if (pattern_matches(p, v.path) || (!v.address.empty() && pattern_matches(p, v.address)))
      return true;
  return false;
}

int print_reply(const std::optional<softplc_hmi::reply_t>& r, const std::string& err) {
  if (!r) {
    std::cerr << "plcctl: " << err << "\n";
    return 1;
  }
  for (const auto& v : r->values) {
    if (!v.error.empty())
      std::cout << v.path << ": " << v.error << "\n";
    else
      std::cout << v.path << " = " << v.text << "  (" << v.type
                << (v.address.empty() ? "" : " " + v.address) << (v.forced ? ", forced" : "")
                << ")\n";
  }
  if (!r->ok) {
    std::cerr << "plcctl: refused: " << r->refusal << (r->refusal.back() == '\n' ? "" : "\n");
    return 1;
  }
  std::cout << r->text;
  return 0;
}

int cmd_watch(Client& c, const std::vector<std::string>& patterns, const Span& span) {
  std::string err;
  auto d = c.describe(err);
  if (!d) {
    std::cerr << "plcctl: " << err << "\n";
    return 1;
  }
  std::map<int, std::string> wanted;  // index -> path
  for (int i = 0; i < d->n; ++i)
    if (matches_any(patterns, d->vars[std::size_t(i)]) && d->vars[std::size_t(i)].published)
      wanted[i] = d->vars[std::size_t(i)].path;
  if (wanted.empty()) {
    std::cerr << "plcctl: watch: no published variable matches (plcctl list shows which are; "
                 "the cell's hmi: publish chooses them)\n";
    return 1;
  }
  const bool tty = isatty(STDOUT_FILENO) != 0;
  std::map<int, std::string> shown;
  std::uint64_t seen = 0;
  bool drawn = false;
  struct Ctx {
    std::map<int, std::string>* wanted;
    std::map<int, std::string>* shown;
    bool tty;
    std::uint64_t* seen;
    bool* drawn;
    void on(const softplc_hmi::values_t& msg) {
      const softplc_hmi::values_t* m = &msg;
      bool any = false;
      for (const auto& v : m->values) {
        auto it = wanted->find(v.index);
        if (it == wanted->end()) continue;
        any = true;
        if (!tty)
          std::printf("%.6f %s = %s\n", double(m->plc_time_ns) / 1e9, it->second.c_str(),
                      v.text.c_str());
        (*shown)[v.index] = v.text;
      }
      if (!any) return;
      ++*seen;
      if (tty) {
        if (*drawn) std::printf("\033[%zuA", wanted->size() + 1);
        std::printf("\033[Kcell %s  task %s  scan %lld  t=%.3f s\n", m->cell.c_str(),
                    m->task.c_str(), static_cast<long long>(m->scan), double(m->plc_time_ns) / 1e9);
        for (const auto& [i, path] : *wanted) {
          auto s = shown->find(i);
          std::printf("\033[K  %-40s %s\n", path.c_str(),
                      s == shown->end() ? "?" : s->second.c_str());
        }
        *drawn = true;
      }
      std::fflush(stdout);
    }
  } ctx{&wanted, &shown, tty, &seen, &drawn};
  auto* s = subscribe_checked<softplc_hmi::values_t>(c.transport(), c.channels().values, &ctx);
  // Bounded by --for/--count; Ctrl-C ends it. Each wait is at most 100 ms.
  while (!span.over(seen)) c.transport().handle_timeout(100);
  c.transport().unsubscribe(s);
  return seen ? 0 : 1;
}

// Alarm events (PREFIX_ALARM) as lines, until --for/--count or Ctrl-C.
int cmd_alarm_events(Client& c, const Span& span) {
  struct Printer {
    std::uint64_t seen = 0;
    void on(const softplc_hmi::alarm_t& a) {
      std::printf("%s %s: %s\n", a.active ? "ALARM" : "CLEARED", a.source.c_str(), a.text.c_str());
      std::fflush(stdout);
      ++seen;
    }
  } p;
  auto* s = subscribe_checked<softplc_hmi::alarm_t>(c.transport(), c.channels().alarm, &p);
  while (!span.over(p.seen)) c.transport().handle_timeout(100);
  c.transport().unsubscribe(s);
  return 0;
}

int cmd_log(Client& c, const std::string& file, const Span& span) {
  // lcm's own writer: the lcm-logger file format (lcm-logplayer replays it).
  lcm::LogFile log(file, "w");
  if (!log.good()) {
    std::cerr << "plcctl: log: cannot write '" << file << "'\n";
    return 1;
  }
  struct Ctx {
    lcm::LogFile* log;
    std::int64_t n = 0;
    void write(const ReceiveBuffer& rb, const std::string& channel) {
      lcm::LogEvent e{};
      e.eventnum = n++;
      e.timestamp = rb.recv_utime;
      e.channel = channel;
      e.datalen = std::int32_t(rb.data_size);
      e.data = const_cast<void*>(rb.data);
      log->writeEvent(&e);
    }
  } ctx{&log};
  // Raw bytes, not decoded (lcm-logger's behaviour).
  auto* s = c.transport().subscribe(
      c.channels().values.substr(0, c.channels().values.size() - 6) + ".*",
      [&ctx](const ReceiveBuffer& rb, const std::string& channel) { ctx.write(rb, channel); });
  while (!span.over(std::uint64_t(ctx.n))) c.transport().handle_timeout(100);
  c.transport().unsubscribe(s);
  std::fprintf(stderr, "plcctl: log: %lld events into %s\n", static_cast<long long>(ctx.n),
               file.c_str());
  return 0;
}

int cmd_trend(Client& c, const std::vector<std::string>& patterns, const std::string& png,
              const std::string& csv, const Span& span) {
  std::string err;
  auto d = c.describe(err);
  if (!d) {
    std::cerr << "plcctl: " << err << "\n";
    return 1;
  }
  Trend tr;
  std::map<int, std::size_t> col;
  for (int i = 0; i < d->n; ++i)
    if (matches_any(patterns, d->vars[std::size_t(i)]) && d->vars[std::size_t(i)].published) {
      col[i] = tr.names.size();
      tr.names.push_back(d->vars[std::size_t(i)].path);
      tr.types.push_back(d->vars[std::size_t(i)].type);
    }
  if (tr.names.empty()) {
    std::cerr << "plcctl: trend: no published variable matches\n";
    return 1;
  }
  tr.value.resize(tr.names.size());
  struct Ctx {
    Trend* tr;
    std::map<int, std::size_t>* col;
    void on(const softplc_hmi::trace_sample_t& msg) {
      const softplc_hmi::trace_sample_t* m = &msg;
      std::vector<double> row(tr->names.size(), std::nan(""));
      bool any = false;
      for (int k = 0; k < m->n; ++k) {
        auto it = col->find(m->index[std::size_t(k)]);
        if (it == col->end()) continue;
        row[it->second] = m->value[std::size_t(k)];
        any = true;
      }
      if (!any) return;
      tr->t.push_back(double(m->plc_time_ns) / 1e9);
      for (std::size_t j = 0; j < row.size(); ++j) tr->value[j].push_back(row[j]);
    }
  } ctx{&tr, &col};
  auto* s = subscribe_checked<softplc_hmi::trace_sample_t>(c.transport(), c.channels().trace, &ctx);
  while (!span.over(tr.t.size())) c.transport().handle_timeout(100);
  c.transport().unsubscribe(s);
  if (!csv.empty()) err = write_trend_csv(tr, csv);
  if (err.empty() && !png.empty()) err = write_trend_png(tr, png, d->cell);
  if (!err.empty()) {
    std::cerr << "plcctl: trend: " << err << "\n";
    return 1;
  }
  std::fprintf(stderr, "plcctl: trend: %zu samples of %zu variable(s)\n", tr.t.size(),
               tr.names.size());
  return 0;
}

int run(int argc, char** argv) {
  po::options_description opts(kUsage + std::string("\nOptions"));
  // clang-format off
  opts.add_options()
    ("help,h", "show this help")
    ("url", po::value<std::string>()->default_value(kDefaultHmiUrl), "LCM url of the cell's bridge (its hmi: url)")
    ("prefix", po::value<std::string>()->default_value("PLC"), "channel prefix (the cell's hmi: prefix)")
    ("key", po::value<std::string>()->value_name("FILE"), "shared key file (the cell's hmi: key_file): sign commands")
    ("timeout", po::value<int>()->default_value(2000)->value_name("MS"), "how long to wait for an answer")
    ("for", po::value<std::string>()->value_name("DURATION"), "watch, log, trend, alarms: stop after this long (e.g. 10s)")
    ("count", po::value<std::uint64_t>()->value_name("N"), "watch: updates, log: events, trend: samples, alarms: events")
    ("png", po::value<std::string>()->value_name("FILE"), "trend: draw into a PNG (PLplot)")
    ("csv", po::value<std::string>()->value_name("FILE"), "trend: write a CSV")
    ("args", po::value<std::vector<std::string>>(), "command and arguments");
  // clang-format on
  po::positional_options_description pos;
  pos.add("args", -1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(argc, argv).options(opts).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const std::exception& e) {
    std::cerr << "plcctl: " << e.what() << "\n";
    return 2;
  }
  if (vm.count("help")) {
    std::cout << opts;
    return 0;
  }
  if (!vm.count("args")) {
    std::cerr << kUsage;
    return 2;
  }
  std::vector<std::string> a = vm["args"].as<std::vector<std::string>>();
  const std::string cmd = a.front();
  a.erase(a.begin());

  Span span;
  if (vm.count("for")) {
    const auto t = parse_iec_time(vm["for"].as<std::string>());
    if (!t || t->count() <= 0) {
      std::cerr << "plcctl: --for: '" << vm["for"].as<std::string>()
                << "' is not a positive duration (e.g. 10s)\n";
      return 2;
    }
    span.end = std::chrono::steady_clock::now() + std::chrono::nanoseconds(t->count());
  }
  if (vm.count("count")) span.count = vm["count"].as<std::uint64_t>();

  std::optional<Key> key;
  if (vm.count("key")) {
    std::string err;
    key = load_key(vm["key"].as<std::string>(), err);
    if (!key) {
      std::cerr << "plcctl: --key: " << err << "\n";
      return 2;
    }
  }
  const int timeout = vm["timeout"].as<int>();
  if (timeout < 1 || timeout > 600000) {
    std::cerr << "plcctl: --timeout: " << timeout << " out of range [1, 600000] ms\n";
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  std::unique_ptr<Client> c;
  try {
    c = std::make_unique<Client>(vm["url"].as<std::string>(), vm["prefix"].as<std::string>(), key,
                                 std::chrono::milliseconds(timeout));
  } catch (const std::exception& e) {
    std::cerr << "plcctl: " << e.what() << "\n";
    return 1;
  }
  auto usage = [&](const char* u) {
    std::cerr << "usage: plcctl " << u << "\n";
    return 2;
  };
  std::string err;
  if (cmd == "list") {
    if (a.size() > 1) return usage("list [PATTERN]");
    auto d = c->describe(err);
    if (!d) {
      std::cerr << "plcctl: " << err << "\n";
      return 1;
    }
    for (const auto& v : d->vars)
      if (a.empty() || matches_any(a, v))
        std::cout << v.path << " " << v.type << (v.address.empty() ? "" : " " + v.address)
                  << (v.published ? " published" : "") << (v.writable ? " w" : "")
                  << (v.forceable ? " f" : "") << "\n";
    return 0;
  }
  if (cmd == "watch") {
    if (a.empty()) return usage("watch PATTERN...");
    return cmd_watch(*c, a, span);
  }
  if (cmd == "trend") {
    if (a.empty() || (!vm.count("png") && !vm.count("csv")))
      return usage("trend PATTERN... (--png FILE | --csv FILE) [--for DURATION | --count N]");
    if (!vm.count("for") && !vm.count("count"))
      span.end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    return cmd_trend(*c, a, vm.count("png") ? vm["png"].as<std::string>() : "",
                     vm.count("csv") ? vm["csv"].as<std::string>() : "", span);
  }
  if (cmd == "log") {
    if (a.size() != 1) return usage("log FILE [--for DURATION | --count N]");
    return cmd_log(*c, a[0], span);
  }
  if (cmd == "stats") {
    auto m = c->next<softplc_hmi::stats_t>(c->channels().stats);
    if (!m) {
      std::cerr << "plcctl: no statistics on " << c->channels().stats << " within " << timeout
                << " ms\n";
      return 1;
    }
    for (const auto& t : m->tasks)
      std::printf(
          "task %-12s period %s  scans %lld  overruns %lld  scan min/avg/max %.1f/%.1f/%.1f "
          "us%s%s\n",
          t.name.c_str(), format_iec_time(TIME(t.period_ns)).c_str(),
          static_cast<long long>(t.scans), static_cast<long long>(t.overruns),
          double(t.scan_ns_min) / 1e3, double(t.scan_ns_avg) / 1e3, double(t.scan_ns_max) / 1e3,
          t.stop_reason.empty() ? "" : "  STOPPED: ", t.stop_reason.c_str());
    std::printf(
        "bridge: published %lld, dropped %lld, commands %lld, refused %lld, bad tag %lld, "
        "replayed %lld, malformed %lld\n",
        static_cast<long long>(m->published), static_cast<long long>(m->dropped),
        static_cast<long long>(m->commands), static_cast<long long>(m->refused),
        static_cast<long long>(m->bad_tag), static_cast<long long>(m->replayed),
        static_cast<long long>(m->malformed));
    // The bridge's transport: what it received, delivered and dropped (by
    // reason), the counters that are not zero.
    std::string counts;
    for (std::size_t k = 0; k < std::size_t(m->n_transport); ++k)
      if (m->transport_count[k])
        counts += (counts.empty() ? " " : ", ") + m->transport_counter[k] + " " +
                  std::to_string(m->transport_count[k]);
    if (!counts.empty()) std::printf("transport:%s\n", counts.c_str());
    return 0;
  }
  if (cmd == "devices" || cmd == "alarms") {
    auto m = c->next<softplc_hmi::diagnostics_t>(c->channels().diag);
    if (!m) {
      std::cerr << "plcctl: no diagnostics on " << c->channels().diag << " within " << timeout
                << " ms\n";
      return 1;
    }
    if (cmd == "devices") {
      for (const auto& d : m->devices)
        std::printf(
            "%-16s %-8s plugin %-10s task %-10s in %s (%d bytes)  out %s (%d bytes)  changes "
            "%lld\n  %s\n",
            d.name.c_str(), d.state.c_str(), d.plugin.c_str(), d.task.c_str(), d.input.c_str(),
            d.in_bytes, d.output.c_str(), d.out_bytes, static_cast<long long>(d.changes),
            d.diagnostics.c_str());
      return 0;
    }
    if (m->alarms.empty()) std::printf("no active alarms\n");
    for (const auto& al : m->alarms) std::printf("%s: %s\n", al.source.c_str(), al.text.c_str());
    // --for/--count: then each alarm event as it comes (lost, back).
    if (!vm.count("for") && !vm.count("count")) return 0;
    std::fflush(stdout);
    return cmd_alarm_events(*c, span);
  }
  static const std::map<std::string, std::pair<std::size_t, std::size_t>> arity = {
      {"read", {1, 256}},   {"write", {2, 2}},    {"force", {2, 2}},
      {"unforce", {1, 2}},  {"pause", {0, 0}},    {"step", {0, 1}},
      {"continue", {0, 0}}, {"break", {1, 1000}}, {"delete", {1, 1}}};
  auto it = arity.find(cmd);
  if (it == arity.end()) {
    std::cerr << "plcctl: unknown command '" << cmd << "'\n" << kUsage;
    return 2;
  }
  if (a.size() < it->second.first || a.size() > it->second.second) {
    std::cerr << "plcctl: " << cmd << ": wrong number of arguments\n" << kUsage;
    return 2;
  }
  if (cmd == "break") {  // the condition as one argument, spaces kept
    std::string cond;
    for (const auto& w : a) cond += (cond.empty() ? "" : " ") + w;
    a = {cond};
  }
  return print_reply(c->command(cmd, a, err), err);
}

}  // namespace

// Nothing ends plcctl with an uncaught exception: what escapes run() (a
// file that cannot be written, the LCM link failing) is a message and exit
// code 1.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "plcctl: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "plcctl: an unknown error\n";
  }
  return 1;
}
