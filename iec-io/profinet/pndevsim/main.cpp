// pndevsim: PROFINET IO devices in front of simulated device models, on one
// network interface, in real time (iec-io/profinet/README.md, "pndevsim").
//
//   build/bin/pndevsim CONFIG.yaml [--for 10s]
//
//   interface: veth1            # the Linux interface (needs CAP_NET_RAW)
//   poll: 250us                 # real-time thread period (<= the send clock)
//   control: stdin              # or a FIFO path; line commands, see below
//   devices:
//     - name: conveyor
//       model: hiwin_e1         # a registered device model (as in a cell config)
//       params: {telegram: 111} # the model's params
//       station_name: conveyor  # NameOfStation (default: name)
//       ip: 10.11.0.2           # must be an address of the interface
//       mac: 02:00:00:00:00:02  # optional (default: the interface's)
//       faults: {silent: false, drop_cyclic: 0, delay_cyclic: 0ms,
//                refuse_connect: DB810104, alarm: {kind: diagnosis, after: 2s}}
//
// Control lines (stdin or the FIFO; NAME may be '*'):
//   silent NAME on|off      drop NAME N|all|off      delay NAME DURATION
//   refuse NAME XXXXXXXX|off (PNIO status as 8 hex digits)
//   alarm NAME diagnosis|process      status
// SIGUSR1 toggles "silent" on every device; SIGTERM/SIGINT end it.
// One line per state change: "pndevsim: NAME: connected", "... data exchange",
// "... lost (data hold expired)", "... released", "... refused DB810104".
// Exit code 2 on a bad config or when the interface cannot be opened, 1
// when it fails while it runs. A relative control FIFO path is taken from
// the config file's folder.
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <deque>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "plc/config_path.hpp"
#include "plc/iec_literal.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/sim_host.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/device/pn_device.hpp"
#include "plc/profinet/link/raw_ethernet_port.hpp"
#include "plc/profinet/link/socket_udp_port.hpp"
#include "plc/realtime_thread.hpp"
#include "plc/thread_guard.hpp"

namespace pn = plc::profinet;
namespace io = plc::io;
using std::chrono::nanoseconds;

namespace {

namespace sim_host = plc::io::sim_host;
using sim_host::ConfigError;
using sim_host::g_stop;
using sim_host::g_toggle_silent;
using sim_host::get_time;
using sim_host::mono_ns;
using sim_host::reject_unknown;

std::optional<pn::PnioStatus> parse_status(const std::string& s) {
  if (s.size() != 8 && !(s.size() == 10 && (s.rfind("0x", 0) == 0 || s.rfind("0X", 0) == 0)))
    return std::nullopt;
  const std::string h = s.size() == 10 ? s.substr(2) : s;
  std::uint32_t v = 0;
  for (char c : h) {
    int d = (c >= '0' && c <= '9')   ? c - '0'
            : (c >= 'a' && c <= 'f') ? c - 'a' + 10
            : (c >= 'A' && c <= 'F') ? c - 'A' + 10
                                     : -1;
    if (d < 0) return std::nullopt;
    v = v << 4 | static_cast<std::uint32_t>(d);
  }
  return pn::PnioStatus::from(v);
}

struct ScheduledAlarm {
  pn::AlarmKind kind = pn::AlarmKind::Diagnosis;
  nanoseconds after{0};
  bool armed = false;
  nanoseconds since{-1};
};

struct Hosted {
  std::string name;
  std::unique_ptr<pn::PnDevice> dev;
  ScheduledAlarm alarm;
};

// Commands go from the control reader (main thread) to the real-time thread,
// events the other way; both through one mutex-guarded queue each.
struct Mailbox {
  std::mutex m;
  std::deque<std::string> commands;
  std::deque<std::string> lines;
};

void print_line(const std::string& s) {
  std::fputs(s.c_str(), stdout);
  std::fputc('\n', stdout);
  std::fflush(stdout);
}

// Runs one control line on the devices (real-time thread); returns the
// answer line ("" for none).
std::string run_command(const std::string& line, std::vector<Hosted>& hosted) {
  std::istringstream in(line);
  std::string cmd, name, arg;
  in >> cmd >> name >> arg;
  if (cmd.empty()) return "";
  if (cmd == "status") {
    std::string out;
    for (const auto& h : hosted)
      out +=
          (out.empty() ? "" : "\n") + std::string("pndevsim: ") + h.name + ": " + h.dev->describe();
    return out;
  }
  std::vector<Hosted*> targets;
  for (auto& h : hosted)
    if (name == "*" || h.name == name) targets.push_back(&h);
  if (targets.empty()) return "pndevsim: error: no device '" + name + "'";
  for (Hosted* h : targets) {
    auto& f = h->dev->faults();
    if (cmd == "silent" && (arg == "on" || arg == "off")) {
      f.silent = arg == "on";
    } else if (cmd == "drop") {
      if (arg == "all") {
        f.drop_all_cyclic = true;
      } else if (arg == "off") {
        f.drop_all_cyclic = false;
        f.drop_cyclic = 0;
      } else {
        char* end = nullptr;
        const unsigned long long n = std::strtoull(arg.c_str(), &end, 10);
        if (arg.empty() || *end != '\0') return "pndevsim: error: drop NAME N|all|off";
        f.drop_cyclic = n;
      }
    } else if (cmd == "delay") {
      const auto t = plc::parse_iec_time(arg);
      if (!t || t->count() < 0) return "pndevsim: error: delay NAME DURATION";
      f.delay_cyclic = *t;
    } else if (cmd == "refuse") {
      if (arg == "off") {
        f.refuse_connect.reset();
      } else {
        const auto st = parse_status(arg);
        if (!st) return "pndevsim: error: refuse NAME XXXXXXXX|off (8 hex digits)";
        f.refuse_connect = st;
      }
    } else if (cmd == "alarm" && (arg == "diagnosis" || arg == "process")) {
      if (!h->dev->raise_alarm(arg == "process" ? pn::AlarmKind::Process
                                                : pn::AlarmKind::Diagnosis))
        return "pndevsim: " + h->name + ": alarm not sent (no AR, or one still unacknowledged)";
    } else {
      return "pndevsim: error: unknown command '" + line + "'";
    }
  }
  return "pndevsim: ok";
}

void realtime_thread(pn::EthernetPort& eth, std::vector<Hosted>& hosted, Mailbox& mb,
                     nanoseconds period, std::int64_t t0, std::int64_t run_ns) {
  if (const int rc = plc::set_fifo_priority(80); rc != 0)
    plc::warn_fifo_refused("pndevsim", rc, "the devices' cyclic thread runs at normal priority");
  std::array<std::uint8_t, pn::kMaxFrameLength> buf{};
  int toggles_seen = 0;
  std::int64_t next = mono_ns();
  std::vector<std::string> cmds;
  while (!g_stop.load()) {
    const nanoseconds now(mono_ns() - t0);
    if (run_ns >= 0 && now.count() >= run_ns) {
      g_stop = true;
      break;
    }
    {
      std::lock_guard lk(mb.m);
      cmds.assign(mb.commands.begin(), mb.commands.end());
      mb.commands.clear();
    }
    for (const auto& c : cmds) {
      const std::string answer = run_command(c, hosted);
      if (!answer.empty()) {
        std::lock_guard lk(mb.m);
        mb.lines.push_back(answer);
      }
    }
    const int t = g_toggle_silent.load();
    for (; toggles_seen < t; ++toggles_seen)
      for (auto& h : hosted) h.dev->faults().silent = !h.dev->faults().silent;
    // A bounded number of frames per tick: a flood cannot starve the timers.
    for (int i = 0; i < 256; ++i) {
      const std::size_t n = eth.receive(buf, nanoseconds(0));
      if (n == 0) break;
      for (auto& h : hosted) h.dev->on_frame(std::span(buf.data(), n), now);
    }
    for (auto& h : hosted) {
      h.dev->poll(now);
      ScheduledAlarm& a = h.alarm;
      if (a.armed) {
        if (h.dev->state() != pn::PnDeviceState::DataExchange) {
          a.since = nanoseconds(-1);
        } else if (a.since.count() < 0) {
          a.since = now;
        } else if (now - a.since >= a.after && h.dev->raise_alarm(a.kind)) {
          a.armed = false;
        }
      }
    }
    next += period.count();
    const std::int64_t late = mono_ns() - next;
    if (late > 0) next += (late / period.count() + 1) * period.count();  // skip, never burst
    timespec ts{static_cast<time_t>(next / 1'000'000'000), static_cast<long>(next % 1'000'000'000)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
  }
}

int run(int argc, char** argv) {
  const auto args = sim_host::parse_args("pndevsim", argc, argv);
  if (!args) return 2;
  const std::string& file = args->config;
  const std::int64_t run_ns = args->run_ns;

  std::unique_ptr<pn::RawEthernetPort> eth;
  std::vector<Hosted> hosted;
  nanoseconds period = std::chrono::microseconds(250);
  std::string control = "stdin";
  const bool loaded = sim_host::load_config("pndevsim", file, [&](const YAML::Node& root) {
    reject_unknown(root, {"interface", "poll", "control", "devices"});
    if (!root["interface"])
      throw ConfigError(root, "key 'interface' missing (a network interface)");
    period = get_time(root, "poll", period);
    if (period < std::chrono::microseconds(50) || period > std::chrono::milliseconds(4))
      throw ConfigError(root["poll"], "key 'poll': between 50us and 4ms");
    if (root["control"]) control = root["control"].as<std::string>();
    // A FIFO's relative path is taken from the config file's folder.
    if (control != "stdin" && control != "none") control = plc::config_relative_path(file, control);
    const YAML::Node devs = root["devices"];
    if (!devs || !devs.IsSequence() || devs.size() == 0)
      throw ConfigError(devs ? devs : root, "key 'devices': a list of at least one device");

    struct Parsed {
      std::string name;
      std::unique_ptr<io::DeviceModel> model;
      pn::PnDeviceConfig cfg;
      pn::PnDeviceFaults faults;
      ScheduledAlarm alarm;
    };
    std::vector<Parsed> parsed;
    bool other_macs = false;
    for (const YAML::Node& d : devs) {
      reject_unknown(d, {"name", "model", "params", "station_name", "ip", "mac", "faults"});
      if (!d["model"]) throw ConfigError(d, "key 'model' missing");
      if (!d["ip"]) throw ConfigError(d, "key 'ip' missing");
      Parsed p;
      const std::string model = d["model"].as<std::string>();
      p.name = d["name"] ? d["name"].as<std::string>() : model;
      io::ModelParams params;
      params.set_folder(plc::config_folder(file));
      if (d["params"]) {
        if (!d["params"].IsMap()) throw ConfigError(d["params"], "key 'params': a map");
        for (const auto& kv : d["params"])
          params.set(kv.first.as<std::string>(), kv.second.as<std::string>());
      }
      const io::DeviceModelFactory* f = io::DeviceModelRegistry::instance().find(model);
      if (!f) throw ConfigError(d["model"], "unknown device model '" + model + "'");
      try {
        p.model = (*f)(params);
        p.cfg.description = pn::builtin_description(model, params);
      } catch (const io::ParamError& e) {
        throw ConfigError(d["params"] ? d["params"] : d,
                          "params: key '" + e.key + "': " + e.what());
      } catch (const std::invalid_argument& e) {
        throw ConfigError(d["model"], e.what());
      }
      p.cfg.description.station_name =
          d["station_name"] ? d["station_name"].as<std::string>() : p.name;
      const auto ip = pn::parse_ipv4(d["ip"].as<std::string>());
      if (!ip) throw ConfigError(d["ip"], "key 'ip': not an IPv4 address (a.b.c.d)");
      p.cfg.description.ip = *ip;
      if (d["mac"]) {
        const auto mac = pn::parse_mac(d["mac"].as<std::string>());
        if (!mac) throw ConfigError(d["mac"], "key 'mac': not a MAC address (02:00:00:00:00:01)");
        p.cfg.mac = *mac;
        other_macs = true;
      }
      if (const YAML::Node fl = d["faults"]) {
        reject_unknown(fl, {"silent", "drop_cyclic", "delay_cyclic", "refuse_connect", "alarm"});
        p.faults.silent = fl["silent"] && fl["silent"].as<bool>();
        if (fl["drop_cyclic"]) {
          const std::string v = fl["drop_cyclic"].as<std::string>();
          if (v == "all") {
            p.faults.drop_all_cyclic = true;
          } else {
            try {
              p.faults.drop_cyclic = fl["drop_cyclic"].as<std::uint64_t>();
            } catch (const YAML::Exception&) {
              throw ConfigError(fl["drop_cyclic"], "key 'drop_cyclic': a count or 'all'");
            }
          }
        }
        p.faults.delay_cyclic = get_time(fl, "delay_cyclic", nanoseconds(0));
        if (fl["refuse_connect"]) {
          p.faults.refuse_connect = parse_status(fl["refuse_connect"].as<std::string>());
          if (!p.faults.refuse_connect)
            throw ConfigError(fl["refuse_connect"],
                              "key 'refuse_connect': a PNIO status as 8 hex digits (DB810104)");
        }
        if (const YAML::Node a = fl["alarm"]) {
          reject_unknown(a, {"kind", "after"});
          const std::string kind = a["kind"] ? a["kind"].as<std::string>() : "diagnosis";
          if (kind != "diagnosis" && kind != "process")
            throw ConfigError(a["kind"], "key 'kind': diagnosis or process");
          p.alarm.kind = kind == "process" ? pn::AlarmKind::Process : pn::AlarmKind::Diagnosis;
          p.alarm.after = get_time(a, "after", nanoseconds(0));
          p.alarm.armed = true;
        }
      }
      for (const Parsed& o : parsed) {
        if (o.name == p.name) throw ConfigError(d, "device name '" + p.name + "' used twice");
        if (o.cfg.description.station_name == p.cfg.description.station_name)
          throw ConfigError(d, "station_name '" + p.cfg.description.station_name + "' used twice");
      }
      parsed.push_back(std::move(p));
    }
    // Several devices (or a MAC of our own) on one interface: every frame to
    // any of them must reach us, so the interface goes promiscuous.
    pn::RawEthernetOptions opt;
    opt.promiscuous = parsed.size() > 1 || other_macs;
    eth = std::make_unique<pn::RawEthernetPort>(root["interface"].as<std::string>(), opt);
    for (Parsed& p : parsed) {
      Hosted h;
      h.name = p.name;
      h.alarm = p.alarm;
      h.dev = std::make_unique<pn::PnDevice>(
          std::move(p.cfg), std::move(p.model), *eth,
          [](pn::Ipv4 ip) { return std::make_unique<pn::SocketUdpPort>(ip, pn::kPnioRpcPort); });
      h.dev->set_shared_port(true);
      h.dev->faults() = p.faults;
      hosted.push_back(std::move(h));
    }
  });
  if (!loaded) return 2;

  Mailbox mb;
  for (auto& h : hosted) {
    const std::string name = h.name;
    h.dev->set_event_sink([&mb, name](const pn::PnDeviceEvent& e) {
      std::lock_guard lk(mb.m);
      mb.lines.push_back("pndevsim: " + name + ": " + pn::describe(e));
    });
  }

  sim_host::install_signals();
  std::signal(SIGPIPE, SIG_IGN);

  int control_fd = -1;
  if (control == "stdin") {
    control_fd = STDIN_FILENO;
  } else if (control != "none") {
    if (mkfifo(control.c_str(), 0600) != 0 && errno != EEXIST) {
      std::fprintf(stderr, "pndevsim: control FIFO %s: %s\n", control.c_str(),
                   std::strerror(errno));
      return 2;
    }
    // O_RDWR keeps the FIFO open when a writer goes away (no endless EOF).
    control_fd = open(control.c_str(), O_RDWR | O_NONBLOCK);
    if (control_fd < 0) {
      std::fprintf(stderr, "pndevsim: control FIFO %s: %s\n", control.c_str(),
                   std::strerror(errno));
      return 2;
    }
  }

  print_line("pndevsim: " + std::to_string(hosted.size()) + " device(s) on " + eth->interface());
  for (const auto& h : hosted)
    print_line("pndevsim: " + h.name + ": " + h.dev->station_name() + " " +
               pn::to_string(h.dev->ip()) + " " + pn::to_string(h.dev->mac()));

  const std::int64_t t0 = mono_ns();
  // The devices' thread failing ends pndevsim (exit code 1): its devices
  // stop answering, and the controller sees them go as on a cut cable.
  std::thread rt([&] {
    plc::run_guarded(
        "device thread", [&] { realtime_thread(*eth, hosted, mb, period, t0, run_ns); },
        [](std::string_view) { g_stop = true; });
  });
  // Should anything below throw, the thread is stopped and joined first (a
  // joinable std::thread destroyed would call std::terminate).
  struct JoinOnExit {
    std::thread& t;
    ~JoinOnExit() {
      if (!t.joinable()) return;
      g_stop = true;
      t.join();
    }
  } join_on_exit{rt};
  std::string pending;
  while (!g_stop.load()) {
    pollfd pfd{control_fd, POLLIN, 0};
    const int r = control_fd >= 0 ? poll(&pfd, 1, 20) : (usleep(20'000), 0);
    if (r > 0 && (pfd.revents & (POLLIN | POLLHUP))) {
      char b[512];
      const ssize_t n = read(control_fd, b, sizeof b);
      if (n > 0) {
        pending.append(b, static_cast<std::size_t>(n));
        for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
          std::lock_guard lk(mb.m);
          mb.commands.push_back(pending.substr(0, nl));
          pending.erase(0, nl + 1);
        }
      } else if (n == 0 && control_fd == STDIN_FILENO) {
        control_fd = -1;  // stdin closed: keep running without control
      }
    }
    std::deque<std::string> lines;
    {
      std::lock_guard lk(mb.m);
      lines.swap(mb.lines);
    }
    for (const auto& l : lines) print_line(l);
  }
  rt.join();
  for (const auto& l : mb.lines) print_line(l);
  for (const auto& h : hosted) print_line("pndevsim: " + h.name + ": " + h.dev->describe());
  if (control_fd >= 0 && control_fd != STDIN_FILENO) close(control_fd);
  return plc::thread_failures() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) { return sim_host::guarded_main("pndevsim", run, argc, argv); }
