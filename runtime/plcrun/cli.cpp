#include "cli.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <boost/program_options.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string_view>
#include <thread>
#include <vector>

#include "checks.hpp"
#include "debug_console.hpp"
#include "new_cell.hpp"
#include "plc/cell_config.hpp"
#include "plc/config_path.hpp"
#include "plc/debug/recording.hpp"
#include "plc/debug/trace.hpp"
#include "plc/hmi/host.hpp"
#include "plc/iec_literal.hpp"
#include "plc/profinet/controller/dcp_tool.hpp"
#include "plc/retain/retain_manager.hpp"
#include "plc/runtime.hpp"
#include "plc/thread_guard.hpp"

namespace plc {
namespace {

namespace po = boost::program_options;

Runtime* g_runtime = nullptr;
debug::Debugger* g_debugger = nullptr;
bool g_console = false;            // a debugger session with a console (--debug)
std::atomic<int> g_end_signal{0};  // the signal that ends a debugger session
pthread_t g_main_thread;           // reads the console; set first thing in plcrun_main
static_assert(std::atomic<int>::is_always_lock_free);  // so async-signal-safe

// First Ctrl-C or SIGTERM: stop at the next scan boundary with outputs safe.
// Second: leave at once (a program stuck in an endless loop never reaches a
// boundary in virtual time).
// In a debugger session with a console, Ctrl-C only interrupts the running
// command (the console goes on); SIGTERM, and Ctrl-C without a console
// (--commands alone), end the session the same way as a run ends.
extern "C" void on_signal(int sig) {
  // The kernel may give the signal to any thread (a task's, a plugin's); a
  // console blocked in read() is woken only by one delivered to its own
  // thread, so hand it over (pthread_kill is async-signal-safe).
  if (!pthread_equal(pthread_self(), g_main_thread)) {
    pthread_kill(g_main_thread, sig);
    return;
  }
  static std::atomic<int> count{0};
  if (g_debugger && g_console && sig == SIGINT) {
    g_debugger->interrupt();
    return;
  }
  if (count.fetch_add(1) > 0) _exit(128 + sig);
  if (g_debugger) {
    g_end_signal.store(sig);
    g_debugger->request_end();
    if (g_console) {
      // A console waiting for a line (libedit retries a read after EINTR)
      // reads end of input instead, so the session ends now too.
      const int fd = open("/dev/null", O_RDONLY);
      if (fd >= 0) {
        dup2(fd, STDIN_FILENO);
        close(fd);
      }
    }
    return;
  }
  if (g_runtime) g_runtime->request_stop();
}

std::string us(std::uint64_t ns) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f us", double(ns) / 1000.0);
  return b;
}

std::vector<std::string> split_csv(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

// A one-line live status (checked every 256 scans so the clock read stays
// off the hot path). In real time every task's thread calls the observer:
// the count is atomic, one thread at a time prints (the others skip, never
// wait), and the figures are snapshots of the tasks' statistics. The time
// shown is that of the scan that prints: Runtime::now() follows the
// virtual clock only (in real time it is set when the run ends, and read
// 0 all along).
class StatusLine {
 public:
  StatusLine(Runtime& rt, bool tty) : rt_(rt), tty_(tty), t0_(std::chrono::steady_clock::now()) {
    rt.add_scan_observer([this](const TaskRuntime&, const ScanContext& ctx) {
      if (((calls_.fetch_add(1, std::memory_order_relaxed) + 1) & 255) == 0 &&
          !printing_.test_and_set(std::memory_order_acquire)) {
        maybe_print(ctx.now);
        printing_.clear(std::memory_order_release);
      }
    });
  }
  void done() {
    if (tty_ && printed_) std::fputc('\n', stderr);
  }

 private:
  void maybe_print(TIME scan_time) {
    const auto now = std::chrono::steady_clock::now();
    // A terminal gets a fresh line ten times a second; a log once a second.
    if (now - last_ < (tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(1000)))
      return;
    last_ = now;
    printed_ = true;
    const double wall = std::chrono::duration<double>(now - t0_).count();
    const double sim = std::chrono::duration<double>(scan_time).count();
    // Built piecewise: GCC 12 warns falsely (-Wrestrict) on a chain of '+'.
    std::string line = "[";
    line += rt_.mode() == io::ClockMode::Virtual ? "virtual" : "realtime";
    line += "] t=";
    char b[64];
    std::snprintf(b, sizeof b, "%.2f s", sim);
    line += b;
    for (const auto& t : rt_.tasks()) {
      const TaskStats st = t->stats.snapshot();
      line += "  " + t->name + ": " + std::to_string(st.scans) + " scans, avg " +
              us(std::uint64_t(st.scan_ns.mean())) + ", ovr " + std::to_string(st.overruns);
    }
    if (rt_.mode() == io::ClockMode::Virtual && wall > 0) {
      std::snprintf(b, sizeof b, "  speed %.0fx", sim / wall);
      line += b;
    }
    if (tty_) {
      std::fprintf(stderr, "\r\033[K%s", line.c_str());
    } else {
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    std::fflush(stderr);
  }

  Runtime& rt_;
  bool tty_;
  bool printed_ = false;
  std::atomic<std::uint64_t> calls_{0};
  std::atomic_flag printing_;  // held by the thread that prints
  std::chrono::steady_clock::time_point t0_, last_{};
};

// `retained`: how the run started from the retain file (none: no retain).
void print_summary(const Runtime& rt, const retain::StartReport* retained) {
  const double sim = std::chrono::duration<double>(rt.now()).count();
  std::printf("== summary: cell '%s', %s time ==\n", rt.cell_name().c_str(),
              rt.mode() == io::ClockMode::Virtual ? "virtual" : "real");
  // First, so that a warm start that fell back to a cold one is not missed.
  if (retained) std::printf("retain: %s\n", retained->headline().c_str());
  std::printf("simulated time: %.3f s   wall time: %.3f s", sim, rt.wall_seconds());
  if (rt.mode() == io::ClockMode::Virtual && rt.wall_seconds() > 0)
    std::printf("   virtual-to-real speed: %.0fx", sim / rt.wall_seconds());
  std::printf("\n");
  for (const auto& t : rt.tasks()) {
    const TaskStats s = t->stats.snapshot();
    std::printf(
        "task %-10s period %-10s cycles %-9llu overruns %llu (skipped %llu)\n", t->name.c_str(),
        format_iec_time(t->period).c_str(), static_cast<unsigned long long>(s.scans),
        static_cast<unsigned long long>(s.overruns), static_cast<unsigned long long>(s.skipped));
    std::printf("  scan time   min %s  avg %s  p99 %s  max %s\n", us(s.scan_ns.min()).c_str(),
                us(std::uint64_t(s.scan_ns.mean())).c_str(), us(s.scan_ns.percentile(0.99)).c_str(),
                us(s.scan_ns.max()).c_str());
    if (s.latency_ns.count())
      std::printf("  wake latency min %s  avg %s  p99 %s  p99.9 %s  max %s\n",
                  us(s.latency_ns.min()).c_str(), us(std::uint64_t(s.latency_ns.mean())).c_str(),
                  us(s.latency_ns.percentile(0.99)).c_str(),
                  us(s.latency_ns.percentile(0.999)).c_str(), us(s.latency_ns.max()).c_str());
    if (!s.stop_reason.empty()) std::printf("  STOPPED: %s\n", s.stop_reason.c_str());
  }
  // Per device, its plugin's own account: state and counters (the
  // DeviceNet scanner: allocations, polls, timeouts, bad frames, bus state).
  // A plugin whose thread failed says so first.
  for (const auto& d : rt.devices())
    if (d.plugin)
      std::printf("device %-10s (%s): %s%s\n", d.name.c_str(), d.plugin_name.c_str(),
                  d.plugin->failed() ? ("FAILED (" + d.plugin->failure() + "); ").c_str() : "",
                  d.plugin->diagnostics(d.index).c_str());
  if (!rt.failure().empty())
    std::printf("STOPPED: %s; outputs at their safe values\n", rt.failure().c_str());
}

// --print-vars: the chosen variables' values after the last scan.
void print_final_values(const Runtime& rt, const std::string& paths) {
  std::printf("final values:\n");
  for (const auto& p : split_csv(paths)) {
    const VarInfo* v = rt.vars().find(p);
    std::printf("  %s = %s\n", p.c_str(),
                v ? VarRegistry::format(*v).c_str() : "<unknown variable>");
  }
}

// A controlled stop saves the last state (the scans are over) and says
// what the writer did. False when the final save failed.
// Thrown from the debugger's first build when the retain start is refused
// (every copy damaged, on_damage_policy says stop): the cell must not run.
struct RetainRefused {};

bool report_retain_stop(retain::Manager& retained) {
  const std::string err = retained.stop();
  const retain::WriterStats st = retained.stats();
  std::fprintf(
      stderr,
      "plcrun: retain: %llu saves (last sequence %llu), %llu unchanged, %llu skipped "
      "(writer busy), %llu failed\n",
      static_cast<unsigned long long>(st.written), static_cast<unsigned long long>(st.sequence),
      static_cast<unsigned long long>(st.unchanged), static_cast<unsigned long long>(st.skipped),
      static_cast<unsigned long long>(st.failed));
  if (err.empty()) return true;
  std::fprintf(stderr, "plcrun: retain: the final save FAILED: %s\n", err.c_str());
  return false;
}

// plcrun itself; `running` turns true once the cell runs (plcrun_main's
// exit code for an exception that escapes).
int run_plcrun(int argc, char** argv, bool& running) {
  g_main_thread = pthread_self();
  po::options_description opts(
      "Usage: plcrun CONFIG [options]\n\nRuns a cell (tasks, programs, devices) from its YAML "
      "config.\n\nOptions");
  // clang-format off
  opts.add_options()
    ("help,h", "show this help")
    ("virtual", "virtual time: no sleeping, devices step in lockstep, reproducible (the default unless the config says clock: realtime)")
    ("realtime", "real time: CLOCK_MONOTONIC absolute sleeps, SCHED_FIFO where permitted")
    ("cycles", po::value<std::uint64_t>()->value_name("N"), "run N periods of the fastest task")
    ("for", po::value<std::string>()->value_name("DURATION"), "run for a duration of (virtual or real) time, e.g. 10s, T#1m30s")
    ("trace", po::value<std::string>()->value_name("FILE"), "write a trace, one row per scan: FILE.csv, or FILE.vcd for GTKWave")
    ("trace-vars", po::value<std::string>()->value_name("PATH,..."), "variables or addresses to trace: PATH,%QW0,...")
    ("trace-trigger", po::value<std::string>()->value_name("CONDITION"), "start tracing when this condition holds, e.g. 'Tank.step = 3'")
    ("trace-pre", po::value<std::size_t>()->value_name("ROWS"), "rows kept from before the trigger (default 0)")
    ("stats-json", po::value<std::string>()->value_name("FILE"), "write per-task statistics as JSON at the end")
    ("checks", po::value<std::string>()->value_name("FILE"), "evaluate the checks in FILE (always:, at_end:, eventually:) during the run; exit code 3 when one of severity error fails")
    ("results-json", po::value<std::string>()->value_name("FILE"), "with --checks: write the checks' verdict, the outputs' final values and a digest of the cell's state as JSON")
    ("list-vars", "print every variable path with its type (and address; 'read-only' for a block's internal state; 'retain' or 'persistent'), then exit")
    ("print-vars", po::value<std::string>()->value_name("PATH,..."), "print these variables' final values after the summary: PATH,PATH,...")
    ("debug", "open the debugger console (pause, step, break, watch, force, trace, goto ...)")
    ("commands", po::value<std::string>()->value_name("FILE"), "run debugger commands from FILE (then the console if --debug)")
    ("record", po::value<std::string>()->value_name("FILE"), "record every scan's device inputs into FILE (for --replay)")
    ("replay", po::value<std::string>()->value_name("FILE"), "replay a recording instead of the devices, checking the outputs")
    ("warm", "warm start: RETAIN and PERSISTENT variables from the retain file; refused when every copy is damaged (unless on_damage: cold)")
    ("warm-or-cold", "warm start when a valid retain file exists, else cold, also when every copy is damaged (the default, whatever on_damage says)")
    ("cold", "cold start: only PERSISTENT variables from the retain file, everything else initial")
    ("reset-retain", "remove the retain file first: every variable at its initial value")
    ("quiet,q", "no live status line")
    ("new-cell", po::value<std::string>()->value_name("DIR"), "write a new cell project (CMake, one program, cell.yaml, a test) into DIR, then exit")
    ("pn-scan", po::value<std::string>()->value_name("IFACE"), "list the PROFINET devices on IFACE (DCP Identify All, 1 s window; needs CAP_NET_RAW), then exit")
    ("pn-set-name", po::value<std::vector<std::string>>()->multitoken()->value_name("IFACE MAC NAME"), "set the NameOfStation of the device with MAC (DCP Set, permanent), then exit")
    ("pn-set-ip", po::value<std::vector<std::string>>()->multitoken()->value_name("IFACE MAC IP[/PREFIX[/GATEWAY]]"), "set the IP suite of the device with MAC (prefix 24, no gateway by default; DCP Set, permanent), then exit")
    ("config", po::value<std::string>()->value_name("FILE"), "the cell config (YAML)");
  // clang-format on
  po::positional_options_description pos;
  pos.add("config", 1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(argc, argv).options(opts).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "plcrun: " << e.what() << "\n(plcrun --help for usage)\n";
    return 2;
  }
  if (vm.count("help")) {
    std::cout << opts << "\n";
    return 0;
  }
  if (vm.count("new-cell")) {
    const std::string dir = vm["new-cell"].as<std::string>();
    const std::string err = write_new_cell(dir);
    if (!err.empty()) {
      std::cerr << "plcrun: --new-cell: " << err << "\n";
      return 2;
    }
    std::cout << "plcrun: wrote a cell project into " << dir << " (see its CMakeLists.txt)\n";
    return 0;
  }
  if (vm.count("pn-scan"))
    return profinet::pn_scan_command(vm["pn-scan"].as<std::string>(), std::cout, std::cerr);
  for (const char* opt : {"pn-set-name", "pn-set-ip"}) {
    if (!vm.count(opt)) continue;
    const auto& a = vm[opt].as<std::vector<std::string>>();
    const bool set_name = std::string_view(opt) == "pn-set-name";
    if (a.size() != 3) {
      std::cerr << "plcrun: --" << opt << " takes IFACE MAC " << (set_name ? "NAME" : "IP")
                << " (plcrun --help for usage)\n";
      return 2;
    }
    return set_name ? profinet::pn_set_name_command(a[0], a[1], a[2], std::cout, std::cerr)
                    : profinet::pn_set_ip_command(a[0], a[1], a[2], std::cout, std::cerr);
  }
  if (!vm.count("config")) {
    std::cerr << "plcrun: missing CONFIG (plcrun --help for usage)\n";
    return 2;
  }
  if (vm["config"].as<std::string>().empty()) {
    std::cerr << "plcrun: CONFIG is an empty path (plcrun --help for usage)\n";
    return 2;
  }
  // Read only once the session has started: checked before anything runs.
  if (vm.count("commands")) {
    const std::string f = vm["commands"].as<std::string>();
    if (const std::string why = readable_file_problem(f); !why.empty()) {
      std::cerr << "plcrun: cannot read command file '" << f << "': " << why << "\n";
      return 2;
    }
  }
  // Where the run's results go must be writable before the cell starts, not
  // found out when the run is over.
  for (const char* opt : {"stats-json", "trace", "record", "results-json"}) {
    if (!vm.count(opt)) continue;
    const std::string f = vm[opt].as<std::string>();
    if (const std::string why = writable_file_problem(f); !why.empty()) {
      std::cerr << "plcrun: --" << opt << ": cannot write '" << f << "': " << why << "\n";
      return 2;
    }
  }
  if (vm.count("virtual") && vm.count("realtime")) {
    std::cerr << "plcrun: --virtual and --realtime exclude each other\n";
    return 2;
  }
  if (vm.count("cycles") && vm.count("for")) {
    std::cerr << "plcrun: --cycles and --for exclude each other\n";
    return 2;
  }
  if (vm.count("results-json") && !vm.count("checks")) {
    std::cerr << "plcrun: --results-json goes with --checks\n";
    return 2;
  }
  if (vm.count("trace") != vm.count("trace-vars")) {
    std::cerr << "plcrun: --trace and --trace-vars go together\n";
    return 2;
  }

  const std::size_t start_modes =
      vm.count("warm") + vm.count("warm-or-cold") + vm.count("cold") + vm.count("reset-retain");
  if (start_modes > 1) {
    std::cerr << "plcrun: --warm, --warm-or-cold, --cold and --reset-retain exclude each other\n";
    return 2;
  }
  const bool start_mode_given = start_modes > 0;

  std::unique_ptr<Runtime> rt;
  io::ClockMode mode = io::ClockMode::Virtual;
  CellConfig cfg;
  try {
    cfg = load_cell_config(vm["config"].as<std::string>());
    mode = cfg.clock.value;
    rt = std::make_unique<Runtime>(cfg);
  } catch (const ConfigError& e) {
    std::cerr << (e.file.empty() ? "plcrun: " : "") << e.what() << "\n";
    return 2;
  }
  if (vm.count("virtual")) mode = io::ClockMode::Virtual;
  if (vm.count("realtime")) mode = io::ClockMode::RealTime;

  if (vm.count("list-vars")) {
    for (const VarInfo& v : rt->vars().all()) {
      std::cout << v.path << " " << to_string(v.type);
      if (v.address) std::cout << " " << v.address->to_string();
      // Internal state of a block: print, watch, trace, break; not write,
      // force or init: (reflect.hpp).
      if (v.read_only) std::cout << " read-only";
      if (v.retain != RetainClass::None) std::cout << " " << to_string(v.retain);
      std::cout << "\n";
    }
    return 0;
  }

  // The virtual clock needs a useful common tick (Runtime::kMaxTicksPerRelease).
  if (mode == io::ClockMode::Virtual && rt->virtual_clock_error()) {
    std::cerr << rt->virtual_clock_error()->what() << "\n";
    return 2;
  }

  // Default span: 10 s in virtual time; in real time until Ctrl-C.
  TIME span = mode == io::ClockMode::Virtual ? TIME(std::chrono::seconds(10))
                                             : TIME(std::chrono::hours(24 * 365));
  // Runs end within kMaxRunSpan, so the clock stays inside TIME's range.
  if (vm.count("cycles")) {
    const std::uint64_t n = vm["cycles"].as<std::uint64_t>();
    const std::uint64_t most = std::uint64_t(kMaxRunSpan / rt->fastest_period());
    if (n < 1 || n > most) {
      std::cerr << "plcrun: --cycles: " << n << " out of range [1, " << most << "] ("
                << format_iec_time(kMaxRunSpan) << " of periods of "
                << format_iec_time(rt->fastest_period()) << ")\n";
      return 2;
    }
    span = rt->fastest_period() * static_cast<std::int64_t>(n);
  }
  if (vm.count("for")) {
    const auto t = parse_iec_time(vm["for"].as<std::string>());
    if (!t || t->count() <= 0 || *t > kMaxRunSpan) {
      std::cerr << "plcrun: --for: '" << vm["for"].as<std::string>()
                << "' is not a duration from 1ns to " << format_iec_time(kMaxRunSpan)
                << " (e.g. 10s)\n";
      return 2;
    }
    span = *t;
  }
  if (vm.count("trace-pre") &&
      vm["trace-pre"].as<std::size_t>() > debug::Trace::kMaxPretriggerRows) {
    std::cerr << "plcrun: --trace-pre: " << vm["trace-pre"].as<std::size_t>()
              << " out of range [0, " << debug::Trace::kMaxPretriggerRows << "]\n";
    return 2;
  }

  if (start_mode_given && !cfg.retain.present) {
    std::cerr << "plcrun: --warm/--warm-or-cold/--cold/--reset-retain: the config has no 'retain:' "
                 "section\n";
    return 2;
  }
  // A cell with an `hmi:` section runs as a debugger session (the bridge's
  // commands are served by the debugger core), without a console unless
  // --debug asks for one.
  const bool hmi = cfg.hmi.present;
  const bool console = vm.count("debug") || vm.count("commands");
  if (console && vm.count("trace")) {
    // A debugger session's trace is the debugger's own; --trace would be
    // silently left out.
    std::cerr << "plcrun: --trace applies to a plain run or a cell with an hmi: section; in a "
                 "--debug or --commands session use the debugger's trace (trace add NAME..., "
                 "trace start FILE)\n";
    return 2;
  }
  if (console && vm.count("print-vars")) {
    // A session can goto, restart and run on after its last command: it
    // has no "final" values; the debugger prints them when asked.
    std::cerr << "plcrun: --print-vars applies to a plain run or a cell with an hmi: section; in "
                 "a --debug or --commands session use the debugger's print (print NAME...)\n";
    return 2;
  }
  // A replay and a console session in virtual time (goto and restart re-run
  // from the start) need the initial values; they neither load nor save
  // retain data. In real time goto and restart are refused: a console
  // session there never rebuilds its runtime, and keeps retain as a plain
  // run does (so that an online change, `reload`, can carry it).
  const bool virtual_console = console && mode == io::ClockMode::Virtual;
  if (start_mode_given && (vm.count("replay") || virtual_console)) {
    std::cerr << "plcrun: --warm/--warm-or-cold/--cold/--reset-retain apply to a plain run, a "
                 "cell with an hmi: section or a real-time debugger session, not to --replay or a "
                 "virtual-time --debug or --commands session\n";
    return 2;
  }
  // Whether this run loads and saves retain data: its file must be
  // writable before anything starts, not at the first save.
  const bool uses_retain = cfg.retain.present && !vm.count("replay") && !virtual_console;
  if (uses_retain) {
    try {
      retain::check_file(cfg);
    } catch (const ConfigError& e) {
      std::cerr << e.what() << "\n";
      return 2;
    }
  }
  // An HMI alone (no console) never rebuilds the runtime (the bridge has no
  // goto or restart): retain is loaded and saved exactly as in a plain run.
  const retain::StartMode start_mode = vm.count("warm")           ? retain::StartMode::Warm
                                       : vm.count("warm-or-cold") ? retain::StartMode::WarmOrCold
                                       : vm.count("cold")         ? retain::StartMode::Cold
                                       : vm.count("reset-retain") ? retain::StartMode::Reset
                                                                  : retain::StartMode::Auto;

  if (vm.count("replay") && mode == io::ClockMode::RealTime) {
    std::cerr << "plcrun: --replay runs in virtual time\n";
    return 2;
  }
  if (vm.count("replay") && vm.count("record")) {
    std::cerr << "plcrun: --replay and --record exclude each other\n";
    return 2;
  }

  if (vm.count("checks") && (console || hmi)) {
    // A session can goto and restart: its run has no single verdict. A
    // failure found by --checks is stepped to with goto in a --replay session.
    std::cerr << "plcrun: --checks applies to a plain run or a --replay, not to --debug, "
                 "--commands or a cell with an hmi: section\n";
    return 2;
  }

  if (console || hmi) {
    // The HMI: its bridge runs as plchmi, its own unprivileged process that
    // this host starts, watches and restarts (hmi-bridge/README.md).
    std::unique_ptr<hmi::Host> bridge;
    // Declared before the debugger, whose first build creates it; reset
    // (hooks removed) before the debugger's runtime goes, by ResetRetain.
    std::unique_ptr<retain::Manager> retained;
    if (hmi) {
      try {
        bridge = std::make_unique<hmi::Host>(cfg.hmi, cfg.file, hmi::Host::Options{});
      } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return 2;
      }
    }
    if (cfg.retain.present && !uses_retain)
      std::fprintf(stderr,
                   "plcrun: retain: not loaded or saved in a virtual-time debugger session or a "
                   "replay (every variable starts at its initial value; goto re-runs from "
                   "them)\n");
    rt.reset();  // the debugger builds (and for goto rebuilds) its own
    debug::Debugger::Options o;
    o.mode = mode;
    o.span = span;
    if (vm.count("replay")) o.replay_file = vm["replay"].as<std::string>();
    if (vm.count("record")) o.record_file = vm["record"].as<std::string>();
    retain::StartReport retain_start;
    o.on_build = [&, b = bridge.get()](Runtime& r) {
      if (uses_retain && !retained) {  // the first (and only) build: before its first scan
        retained = std::make_unique<retain::Manager>(r, cfg.retain);
        retain_start = retained->start(start_mode);
        for (const auto& line : retain_start.lines())
          std::fprintf(stderr, "plcrun: retain: %s\n", line.c_str());
        // Before the runtime starts (Debugger::build): no scan runs.
        if (retain_start.refused) throw RetainRefused();
        if (b && retain_start.fell_back())
          b->add_start_alarm("retain_cold_start", "retain", retain_start.headline());
      }
      // After the retain start: the layout the bridge gets carries its alarm.
      if (b) b->attach(r);
    };
    std::unique_ptr<debug::Debugger> dbg;
    try {
      dbg = std::make_unique<debug::Debugger>([&cfg] { return std::make_unique<Runtime>(cfg); }, o);
    } catch (const RetainRefused&) {
      return 1;
    } catch (const debug::RecordingError& e) {
      std::cerr << "plcrun: " << e.what() << "\n";
      return 1;
    } catch (const std::exception& e) {
      std::cerr << "plcrun: " << e.what() << "\n";
      return 2;
    }
    if (vm.count("record"))
      std::cout << "recording every scan's inputs into " << vm["record"].as<std::string>() << "\n";
    struct ResetRetain {
      std::unique_ptr<retain::Manager>& m;
      ~ResetRetain() { m.reset(); }
    } reset_retain{retained};
    // `reload` switches the retain file's layout with the programs.
    dbg->set_retain(retained.get());
    // After the last scan (Debugger::stop_cell): the final save, as a plain
    // run does. False when it failed.
    auto finish_retain = [&retained, &dbg] {
      if (!retained) return true;
      dbg->set_retain(nullptr);
      const bool ok = report_retain_stop(*retained);
      retained.reset();
      return ok;
    };
    // Stopped before the debugger goes (declared after it): plchmi is told
    // to stop and reaped, the host's thread joined.
    struct StopBridge {
      hmi::Host* b;
      ~StopBridge() {
        if (b) b->stop();
      }
    } stop_bridge{bridge.get()};
    if (bridge) {
      bridge->set_debugger(dbg.get());
      bridge->start();
      std::fprintf(stderr, "plcrun: hmi: bridge on %s, channels %s_* (its own process, plchmi)\n",
                   cfg.hmi.url.value.c_str(), cfg.hmi.prefix.value.c_str());
    }
    g_debugger = dbg.get();
    // Forgotten before the debugger goes, however this block is left.
    struct ForgetDebugger {
      ~ForgetDebugger() { g_debugger = nullptr; }
    } forget_debugger;
    running = true;
    g_console = vm.count("debug") != 0;
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    bool retain_failed = false;
    const std::string file = vm.count("commands") ? vm["commands"].as<std::string>() : "";
    if (!vm.count("debug") && !vm.count("commands")) {
      // The HMI only: run the cell, as a plain run would, until the span
      // ends or a signal (real time: the bridge may pause and step it).
      std::fprintf(stderr, "plcrun: running cell '%s' in %s time%s\n", cfg.cell.value.c_str(),
                   mode == io::ClockMode::Virtual ? "virtual" : "real",
                   mode == io::ClockMode::RealTime ? " (Ctrl-C stops, outputs go safe)" : "");
      std::fflush(stderr);
      // --trace through the debugger's trace (the cell's own record of its scans).
      if (vm.count("trace")) {
        for (const auto& v : split_csv(vm["trace-vars"].as<std::string>()))
          std::cout << dbg->execute("trace add " + v);
        const std::string out = dbg->execute("trace start " + vm["trace"].as<std::string>());
        std::cout << out;
        if (out.rfind("trace start:", 0) == 0) return 2;
      }
      std::cout << dbg->continue_running().text;
      const auto end = std::chrono::steady_clock::now() + span;
      while (mode == io::ClockMode::RealTime && !dbg->end_requested() &&
             std::chrono::steady_clock::now() < end)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      if (vm.count("trace")) std::cout << dbg->execute("trace stop");
      if (g_end_signal.load() == 0) {
        if (bridge) bridge->stop();  // no command may restart the cell now
        dbg->stop_cell();
        retain_failed = !finish_retain();
        std::fflush(stdout);
        print_summary(dbg->runtime(), uses_retain ? &retain_start : nullptr);
        if (bridge)
          for (const auto& line : bridge->summary()) std::printf("hmi: %s\n", line.c_str());
        if (vm.count("print-vars"))
          print_final_values(dbg->runtime(), vm["print-vars"].as<std::string>());
      }
    } else if (!run_debug_session(*dbg, file, g_console)) {
      std::cerr << "plcrun: cannot read command file '" << file << "'\n";
      dbg->stop_cell();  // a real-time cell runs already: stop it before its retain goes
      finish_retain();
      g_debugger = nullptr;
      return 2;
    }
    // A recording still running when the session ends is finished here, so
    // that a failure (a full disk) shows and sets the exit code.
    bool recording_failed = false;
    if (dbg->execute("record").rfind("recording,", 0) == 0) {
      const std::string out = dbg->execute("record stop");
      std::cout << out;
      recording_failed = out.find("FAILED") != std::string::npos;
    }
    const int sig = g_end_signal.load();
    if (sig == 0) {
      if (retained) {  // a real-time console session that ended (quit, end of the file)
        if (bridge) bridge->stop();
        dbg->stop_cell();
        retain_failed = !finish_retain();
      }
      g_debugger = nullptr;
      // A thread that failed fails the session (plc/thread_guard.hpp).
      return recording_failed || retain_failed || thread_failures() > 0 ? 1 : 0;
    }
    // Ended by a signal: like a run, every output safe, then the summary.
    if (bridge) bridge->stop();  // no command may reach the cell while it stops
    dbg->stop_cell();
    finish_retain();
    std::fflush(stdout);
    print_summary(dbg->runtime(), uses_retain ? &retain_start : nullptr);
    if (bridge)
      for (const auto& line : bridge->summary()) std::printf("hmi: %s\n", line.c_str());
    if (vm.count("print-vars"))  // only an HMI session gets here with it
      print_final_values(dbg->runtime(), vm["print-vars"].as<std::string>());
    g_debugger = nullptr;
    dbg.reset();
    std::printf("stopped by %s; outputs at their safe values\n",
                sig == SIGTERM ? "SIGTERM" : "SIGINT");
    // 128 + signal, the shell's convention for "ended by this signal": a
    // script or service manager sees that the session was cut short (not 0),
    // and neither a failure of the cell (1) nor bad input (2).
    return 128 + sig;
  }

  std::unique_ptr<debug::Replayer> replayer;
  std::unique_ptr<debug::Recorder> recorder;
  try {
    if (vm.count("replay"))
      replayer = std::make_unique<debug::Replayer>(*rt, vm["replay"].as<std::string>());
    if (vm.count("record"))
      recorder = std::make_unique<debug::Recorder>(*rt, vm["record"].as<std::string>());
  } catch (const debug::RecordingError& e) {
    std::cerr << "plcrun: " << e.what() << "\n";  // damaged, incomplete, other version or cell
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "plcrun: " << e.what() << "\n";
    return 2;
  }

  // A replay needs the initial values the recording started from.
  std::unique_ptr<retain::Manager> retained;
  retain::StartReport retain_start;
  if (uses_retain) {
    retained = std::make_unique<retain::Manager>(*rt, cfg.retain);
    retain_start = retained->start(start_mode);
    for (const auto& line : retain_start.lines())
      std::fprintf(stderr, "plcrun: retain: %s\n", line.c_str());
    if (retain_start.refused) return 1;  // nothing has started
  }

  std::unique_ptr<ScenarioChecks> checks;
  if (vm.count("checks")) {
    try {
      checks =
          std::make_unique<ScenarioChecks>(*rt, load_checks_file(vm["checks"].as<std::string>()));
    } catch (const ConfigError& e) {
      std::cerr << e.what() << "\n";
      return 2;
    }
  }

  std::unique_ptr<debug::Trace> trace;
  if (vm.count("trace")) {
    trace = std::make_unique<debug::Trace>(rt->vars(), rt->image(), rt->byte_order());
    trace->set_backpressure(mode == io::ClockMode::Virtual);
    std::string err;
    for (const auto& v : split_csv(vm["trace-vars"].as<std::string>()))
      if (err.empty()) err = trace->add(v);
    if (err.empty() && vm.count("trace-trigger"))
      err = trace->set_trigger(vm["trace-trigger"].as<std::string>());
    if (vm.count("trace-pre")) trace->set_pretrigger(vm["trace-pre"].as<std::size_t>());
    if (err.empty()) err = trace->start(vm["trace"].as<std::string>());
    if (!err.empty()) {
      std::cerr << "plcrun: trace: " << err << " (plcrun CONFIG --list-vars lists the variables)\n";
      return 2;
    }
    int fastest = 0;
    for (const auto& t : rt->tasks())
      if (t->period == rt->fastest_period()) {
        fastest = static_cast<int>(t->order);
        break;
      }
    const int task = trace->sampling_task(fastest);
    debug::Trace* tr = trace.get();
    rt->add_scan_observer([tr, task](const TaskRuntime& t, const ScanContext& ctx) {
      if (static_cast<int>(t.order) == task) tr->sample(ctx);
    });
  }
  std::unique_ptr<StatusLine> status;
  if (!vm.count("quiet")) status = std::make_unique<StatusLine>(*rt, isatty(STDERR_FILENO) != 0);

  g_runtime = rt.get();
  // Forgotten before the runtime goes, however plcrun leaves.
  struct ForgetRuntime {
    ~ForgetRuntime() { g_runtime = nullptr; }
  } forget_runtime;
  running = true;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  std::fprintf(stderr, "plcrun: running cell '%s' in %s time%s\n", rt->cell_name().c_str(),
               mode == io::ClockMode::Virtual ? "virtual" : "real",
               mode == io::ClockMode::RealTime ? " (Ctrl-C stops, outputs go safe)" : "");
  std::fflush(stderr);
  int rc = 0;
  try {
    if (replayer) {
      // The recording fixes which scans run, in which order, at which time.
      rt->start(io::ClockMode::Virtual);
      while (!rt->stop_requested() && replayer->step()) {
      }
      rt->finish();
      std::printf("replay: %llu scans, %llu with different outputs%s%s\n",
                  static_cast<unsigned long long>(replayer->scans()),
                  static_cast<unsigned long long>(replayer->mismatches()),
                  replayer->first_mismatch() >= 0
                      ? (", first at scan " + std::to_string(replayer->first_mismatch())).c_str()
                      : "",
                  replayer->error().empty() ? "" : (" (" + replayer->error() + ")").c_str());
      if (replayer->mismatches() || !replayer->error().empty()) rc = 1;
    } else {
      rt->run(mode, span);
    }
  } catch (const io::PluginStartError& e) {
    std::cerr << "plcrun: " << e.what() << "\n";
    rc = 1;
  }
  if (recorder) {
    const std::string err = recorder->close();
    if (err.empty()) {
      std::printf("recorded %llu scans into %s\n",
                  static_cast<unsigned long long>(recorder->scans()),
                  vm["record"].as<std::string>().c_str());
    } else {
      std::fprintf(stderr, "plcrun: recording into %s FAILED after %llu scans: %s\n",
                   vm["record"].as<std::string>().c_str(),
                   static_cast<unsigned long long>(recorder->scans()), err.c_str());
      rc = 1;
    }
  }
  g_runtime = nullptr;
  if (retained && !report_retain_stop(*retained)) rc = 1;
  if (status) status->done();
  if (trace) {
    trace->stop();
    if (const std::string err = trace->error(); !err.empty()) {
      std::fprintf(stderr, "plcrun: trace into %s FAILED: %s\n",
                   vm["trace"].as<std::string>().c_str(), err.c_str());
      rc = 1;
    }
  }
  print_summary(*rt, retained ? &retain_start : nullptr);
  if (vm.count("print-vars")) print_final_values(*rt, vm["print-vars"].as<std::string>());
  if (rt->stop_requested()) std::printf("stopped by signal; outputs at their safe values\n");
  for (const auto& t : rt->tasks())
    if (!t->stats.snapshot().stop_reason.empty()) rc = 1;
  // A thread that failed (a plugin's, a writer's, the watchdog, the HMI
  // bridge: plc/thread_guard.hpp) fails the run.
  if (thread_failures() > 0) rc = 1;
  if (checks) {
    checks->finish();
    std::string stop_reason = rt->stop_requested() ? "signal" : "";
    for (const auto& t : rt->tasks())
      if (const std::string r = t->stats.snapshot().stop_reason; !r.empty() && stop_reason.empty())
        stop_reason = r;
    std::fputs(checks->failures_text().c_str(), stdout);
    if (vm.count("results-json")) {
      std::ofstream f(vm["results-json"].as<std::string>());
      f << checks->json(stop_reason);
      if (!f.flush()) {
        std::cerr << "plcrun: cannot write " << vm["results-json"].as<std::string>() << "\n";
        return 1;
      }
    }
    if (rc == 0 && !checks->passed()) rc = 3;
  }
  if (vm.count("stats-json")) {
    std::ofstream f(vm["stats-json"].as<std::string>());
    if (!f) {
      std::cerr << "plcrun: cannot write " << vm["stats-json"].as<std::string>() << "\n";
      return 2;
    }
    f << rt->stats_json();
  }
  return rc;
}

}  // namespace

int plcrun_main(int argc, char** argv) {
  // Every error is a message and an exit code, never std::terminate (the
  // shell's 134): what escapes before the cell runs is about what plcrun was
  // given (2, as a bad config), what escapes once it runs is a failure of
  // the run (1).
  bool running = false;
  try {
    return run_plcrun(argc, argv, running);
  } catch (const std::exception& e) {
    std::cerr << "plcrun: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "plcrun: an unknown error\n";
  }
  return running ? 1 : 2;
}

}  // namespace plc
