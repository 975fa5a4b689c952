// dpslavesim: PROFIBUS-DP slaves in front of simulated devices, on a
// serial line or a pty, in real time.
//
//   build/bin/dpslavesim slaves.yaml [--for 10s]
//
//   transport: serial:/tmp/pb-line   # a tty: an RS-485 adapter, or the pty plcrun made
//                                    # (pty:PATH: make a pty here, PATH -> its slave side)
//   baud: 1500000                    # 8E1; meaningless on a pty
//   capture: slaves.txt              # optional: every telegram, decoded (pcap: FILE too)
//   slaves:
//     - name: scale
//       model: pr5510                # a registered device model (as in a cell config)
//       params: {bus: profibus}      # the model's params
//       address: 5
//       gsd: GWT_5610.gsd            # identity, modules, Max_Module, Freeze/Sync (relative:
//                                    # from this config file's folder)
//       io_bytes: 8                  # the I/O size set at the device (PR5510 menu "I/Os")
//       faults: {silent: false, stat_diag: false, ext_diag: "", ignore_watchdog: false}
//
// SIGUSR1 toggles "silent" on every slave (a pulled line without killing
// the process); SIGTERM/SIGINT end it. Exit code 2 on a bad config.
#include <poll.h>
#include <yaml-cpp/yaml.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "plc/config_path.hpp"
#include "plc/iec_literal.hpp"
#include "plc/io/device_model.hpp"
#include "plc/io/sim_host.hpp"
#include "plc/profibus/dp/describe.hpp"
#include "plc/profibus/fdl/timing.hpp"
#include "plc/profibus/link/capture.hpp"
#include "plc/profibus/link/line.hpp"
#include "plc/profibus/slave/dp_slave.hpp"
#include "plc/profibus/slave/from_gsd.hpp"

namespace pb = plc::profibus;
namespace io = plc::io;

namespace {

namespace sim_host = plc::io::sim_host;
using sim_host::ConfigError;
using sim_host::g_stop;
using sim_host::g_toggle_silent;
using sim_host::get_number;
using sim_host::mono_ns;
using sim_host::reject_unknown;

std::vector<std::uint8_t> hex_bytes(const YAML::Node& n) {
  std::vector<std::uint8_t> out;
  const std::string s = n.as<std::string>();
  std::size_t i = 0;
  while (i < s.size()) {
    if (s[i] == ' ') {
      ++i;
      continue;
    }
    char* end = nullptr;
    const unsigned long v = std::strtoul(s.c_str() + i, &end, 16);
    if (end == s.c_str() + i || v > 255 || end - (s.c_str() + i) > 2)
      throw ConfigError(n, "ext_diag: hex bytes, e.g. \"04 10 20 30\"");
    out.push_back(static_cast<std::uint8_t>(v));
    i = static_cast<std::size_t>(end - s.c_str());
  }
  return out;
}

struct Hosted {
  std::string name;
  std::unique_ptr<pb::slave::DpSlave> slave;
  pb::slave::SlaveState last = pb::slave::SlaveState::WaitPrm;
};

// Tap: the slaves and the capture read the same bytes, so the line is read
// once here and the telegrams' bytes handed to each slave.
class SharedLine final : public pb::link::Line {
 public:
  explicit SharedLine(pb::link::Line& inner) : inner_(inner) {}
  bool send(std::span<const std::uint8_t> t) override {
    if (capture_) {
      pb::fdl::Telegram tg;
      if (pb::fdl::decode(t, tg).status == pb::fdl::DecodeStatus::Ok)
        capture_->record(mono_ns() - t0_, true, t, tg);
    }
    return inner_.send(t);
  }
  std::size_t receive(std::span<std::uint8_t> buf) override {
    const std::size_t n = std::min(buf.size(), pending_.size() - at_);
    std::copy_n(pending_.begin() + static_cast<std::ptrdiff_t>(at_), n, buf.begin());
    at_ += n;
    return n;
  }
  int fd() const override { return inner_.fd(); }
  const pb::link::LineCounters& counters() const override { return inner_.counters(); }
  std::string describe() const override { return inner_.describe(); }
  // Reads what arrived; each slave then receives it from the start.
  void pump() {
    std::array<std::uint8_t, 512> b{};
    pending_.clear();
    for (int i = 0; i < 64; ++i) {
      const std::size_t n = inner_.receive(b);
      if (n == 0) break;
      pending_.insert(pending_.end(), b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
    }
    if (capture_) {
      tap_.push(pending_);
      pb::fdl::Telegram tg;
      std::span<const std::uint8_t> raw;
      while (tap_.next(tg, &raw))
        if (tg.request() || tg.format == pb::fdl::Format::Token)
          capture_->record(mono_ns() - t0_, false, raw, tg);
    }
  }
  void rewind() { at_ = 0; }
  void set_capture(pb::link::Capture* c, std::int64_t t0) {
    capture_ = c;
    t0_ = t0;
  }

 private:
  pb::link::Line& inner_;
  std::vector<std::uint8_t> pending_;
  std::size_t at_ = 0;
  pb::link::Capture* capture_ = nullptr;
  pb::fdl::Deframer tap_;
  std::int64_t t0_ = 0;
};

int run(int argc, char** argv) {
  const auto args = sim_host::parse_args("dpslavesim", argc, argv);
  if (!args) return 2;
  const std::string& file = args->config;
  const std::int64_t run_ns = args->run_ns;

  std::unique_ptr<pb::link::Line> line;
  std::unique_ptr<SharedLine> shared;
  std::unique_ptr<pb::link::Capture> capture;
  std::vector<Hosted> slaves;
  std::string transport;
  const bool loaded = sim_host::load_config("dpslavesim", file, [&](const YAML::Node& root) {
    reject_unknown(root, {"transport", "baud", "capture", "pcap", "slaves"});
    if (!root["transport"])
      throw ConfigError(root, "key 'transport' missing (serial:PATH or pty:PATH)");
    transport = root["transport"].as<std::string>();
    // Files named in this config (the line's device, gsd:, capture:,
    // pcap:): a relative path is taken from the config file's folder.
    for (const char* kind : {"serial:", "pty:"})
      if (transport.rfind(kind, 0) == 0 && transport.size() > std::strlen(kind))
        transport = kind + plc::config_relative_path(file, transport.substr(std::strlen(kind)));
    const auto baud = get_number<std::uint32_t>(root, "baud", 1500000, 9600, 12000000);
    if (!pb::fdl::baud_profile(baud)) throw ConfigError(root["baud"], "not a PROFIBUS baud rate");
    if (!root["slaves"] || !root["slaves"].IsSequence() || root["slaves"].size() == 0)
      throw ConfigError(root, "key 'slaves': a list of at least one slave");
    std::vector<std::pair<pb::slave::SlaveConfig, std::unique_ptr<io::DeviceModel>>> made;
    std::vector<std::string> names;
    for (const YAML::Node& s : root["slaves"]) {
      reject_unknown(s, {"name", "model", "params", "address", "gsd", "io_bytes", "faults"});
      if (!s["model"]) throw ConfigError(s, "key 'model' missing");
      if (!s["address"]) throw ConfigError(s, "key 'address' missing");
      if (!s["gsd"]) throw ConfigError(s, "key 'gsd' missing");
      const std::string model = s["model"].as<std::string>();
      const auto address = get_number<int>(s, "address", 0, 0, 125);
      const auto io_bytes = get_number<int>(s, "io_bytes", 8, 1, 244);
      pb::gsd::Gsd g;
      try {
        g = pb::gsd::load_gsd(plc::config_relative_path(file, s["gsd"].as<std::string>()));
      } catch (const pb::gsd::GsdError& e) {
        throw ConfigError(s["gsd"], e.what());
      }
      auto cfg = pb::slave::slave_config_from_gsd(g, static_cast<std::uint8_t>(address),
                                                  static_cast<std::size_t>(io_bytes),
                                                  static_cast<std::size_t>(io_bytes));
      io::ModelParams params;
      params.set_folder(plc::config_folder(file));
      if (s["params"])
        for (const auto& kv : s["params"])
          params.set(kv.first.as<std::string>(), kv.second.as<std::string>());
      const io::DeviceModelFactory* f = io::DeviceModelRegistry::instance().find(model);
      if (!f) throw ConfigError(s["model"], "unknown device model '" + model + "'");
      std::unique_ptr<io::DeviceModel> m;
      try {
        m = (*f)(params);
      } catch (const io::ParamError& e) {
        throw ConfigError(s["params"] ? s["params"] : s,
                          "params: key '" + e.key + "': " + e.what());
      }
      if (m->input_size() > cfg.input_bytes || m->output_size() > cfg.output_bytes)
        throw ConfigError(s["io_bytes"] ? s["io_bytes"] : s,
                          "io_bytes smaller than the model's window (" +
                              std::to_string(m->input_size()) + " bytes)");
      for (const auto& o : made)
        if (o.first.address == cfg.address) throw ConfigError(s["address"], "address used twice");
      names.push_back(s["name"] ? s["name"].as<std::string>() : model);
      made.emplace_back(cfg, std::move(m));
      if (const YAML::Node fl = s["faults"]) {
        reject_unknown(fl, {"silent", "stat_diag", "ext_diag", "ignore_watchdog"});
      }
    }
    line = pb::link::open_line(transport, baud);
    shared = std::make_unique<SharedLine>(*line);
    if (root["capture"] || root["pcap"])
      capture = std::make_unique<pb::link::Capture>(
          root["capture"] ? plc::config_relative_path(file, root["capture"].as<std::string>()) : "",
          root["pcap"] ? plc::config_relative_path(file, root["pcap"].as<std::string>()) : "");
    std::size_t i = 0;
    for (const YAML::Node& s : root["slaves"]) {
      Hosted h{names[i], std::make_unique<pb::slave::DpSlave>(made[i].first,
                                                              std::move(made[i].second), *shared)};
      if (const YAML::Node fl = s["faults"]) {
        h.slave->faults().silent = fl["silent"] && fl["silent"].as<bool>();
        h.slave->faults().stat_diag = fl["stat_diag"] && fl["stat_diag"].as<bool>();
        h.slave->faults().ignore_watchdog =
            fl["ignore_watchdog"] && fl["ignore_watchdog"].as<bool>();
        if (fl["ext_diag"]) h.slave->faults().ext = hex_bytes(fl["ext_diag"]);
      }
      slaves.push_back(std::move(h));
      ++i;
    }
  });
  if (!loaded) return 2;

  sim_host::install_signals();

  const std::int64_t t0 = mono_ns();
  shared->set_capture(capture.get(), t0);
  int toggles_seen = 0;
  std::printf("dpslavesim: %zu slave(s) on %s\n", slaves.size(), line->describe().c_str());
  std::fflush(stdout);
  while (!g_stop.load()) {
    const std::int64_t now = mono_ns() - t0;
    if (run_ns >= 0 && now >= run_ns) break;
    const int t = g_toggle_silent.load();
    for (; toggles_seen < t; ++toggles_seen)
      for (auto& h : slaves) {
        h.slave->faults().silent = !h.slave->faults().silent;
        std::printf("dpslavesim: %s: %s\n", h.name.c_str(),
                    h.slave->faults().silent ? "silent" : "answering");
        std::fflush(stdout);
      }
    shared->pump();
    for (auto& h : slaves) {
      shared->rewind();
      h.slave->tick(plc::TIME(now));
      if (h.slave->state() != h.last) {
        h.last = h.slave->state();
        std::printf("dpslavesim: %s (address %u): %s\n", h.name.c_str(), h.slave->address(),
                    pb::slave::to_string(h.last));
        std::fflush(stdout);
      }
    }
    // Wake on the next request, or after 1 ms for the devices and watchdogs.
    pollfd pfd{line->fd(), POLLIN, 0};
    (void)poll(&pfd, 1, 1);
    if (pfd.revents & (POLLHUP | POLLERR)) {
      timespec ts{0, 1'000'000};
      nanosleep(&ts, nullptr);
    }
  }
  if (capture) capture->flush();
  for (const auto& h : slaves)
    std::printf("dpslavesim: %s: %s\n", h.name.c_str(), h.slave->describe().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return sim_host::guarded_main("dpslavesim", run, argc, argv); }
