#include "plc/devicenet/devicenet_plugin.hpp"

#include <poll.h>
#include <time.h>

#include <cstdio>
#include <cstring>

#include "plc/devicenet/startup_writes.hpp"
#include "plc/thread_guard.hpp"

namespace plc::devicenet {

// Writes every frame the scanner receives (the whole bus, our own frames
// included, as every backend echoes them) to the pcap file, stamped with
// the scanner's clock.
class DeviceNetPlugin::CapturingBus final : public can::Bus {
 public:
  CapturingBus(can::Bus& inner, can::PcapWriter* pcap) : inner_(inner), pcap_(pcap) {}
  bool send(const can::Frame& f) override { return inner_.send(f); }
  bool receive(can::Frame& f) override {
    if (!inner_.receive(f)) return false;
    if (pcap_) pcap_->write(f, now_ns_);
    return true;
  }
  int fd() const override { return inner_.fd(); }
  can::BusState state() const override { return inner_.state(); }
  const can::BusCounters& counters() const override { return inner_.counters(); }
  void set_time(TIME now) { now_ns_ = now.count(); }

 private:
  can::Bus& inner_;
  can::PcapWriter* pcap_;
  std::int64_t now_ns_ = 0;
};

namespace {
using std::chrono::milliseconds;
using std::chrono::seconds;
}  // namespace

DeviceNetPlugin::~DeviceNetPlugin() { stop(); }

void DeviceNetPlugin::configure(const io::ModelParams& p) {
  cfg_.mac = static_cast<std::uint8_t>(p.get_int("mac", 0, 0, 63));
  // The baud rate is the interface's (ip link ... bitrate); it is kept for
  // the bus-time figures and checked against the three DeviceNet rates.
  const auto baud = p.get_int("baud", 500000, 125000, 500000);
  if (baud != 125000 && baud != 250000 && baud != 500000)
    throw io::ParamError("baud", "baud must be 125000, 250000 or 500000");
  bus_spec_ = p.get_string("bus", "udp:127.0.0.1:47800");
  host_hub_ = p.get_bool("hub", false);
  if (host_hub_ && bus_spec_.rfind("udp:", 0) != 0)
    throw io::ParamError("hub", "hub: true needs a udp:HOST:PORT bus");
  pcap_path_ = p.get_path("pcap");  // a relative file: in the config file's folder
  cfg_.poll_cycle = p.get_time("poll_cycle", cfg_.poll_cycle, milliseconds(1), seconds(10));
  cfg_.dup_mac_wait = p.get_time("dup_mac_wait", cfg_.dup_mac_wait, milliseconds(1), seconds(10));
  cfg_.retry = p.get_time("retry", cfg_.retry, milliseconds(10), seconds(60));
  cfg_.explicit_timeout =
      p.get_time("explicit_timeout", cfg_.explicit_timeout, milliseconds(1), seconds(60));
  cfg_.serial = static_cast<std::uint32_t>(p.get_int("serial", cfg_.serial, 0, 0xFFFFFFFF));
  log_ = p.get_bool("log", true);
  p.reject_unknown();
  scanner_ = std::make_unique<Scanner>(cfg_, nullptr);
  scanner_->on_change = [this](std::size_t d, ScanState st, const std::string& why) {
    if (!log_) return;
    std::fprintf(stderr, "devicenet: %s (MAC %u): %s%s%s\n", entries_[d].name.c_str(),
                 entries_[d].mac,
                 st == ScanState::Online  ? "online"
                 : st == ScanState::Fault ? "fault"
                                          : "lost",
                 why.empty() ? "" : ": ", why.c_str());
  };
}

io::DeviceSizes DeviceNetPlugin::add_device(const io::DeviceSpec& spec) {
  if (!scanner_) scanner_ = std::make_unique<Scanner>(cfg_, nullptr);
  const io::ModelParams& p = spec.params;
  ScanEntry e;
  e.name = spec.name;
  // Profiles fill in what the device's EDS says; the keys override.
  std::int64_t in = -1, out = -1;
  if (spec.model == "pr1721_34") {  // PR5510 with PR1721/34 (sartorius-pr1721.md §2.3)
    in = out = 8;
    e.vendor = 560;
    e.product = 1713;
  } else if (spec.model != "generic") {
    throw io::ParamError(
        "model", "devicenet device model must be generic or pr1721_34, not '" + spec.model + "'");
  }
  e.mac = static_cast<std::uint8_t>(p.get_int("mac", -1, 0, 63));
  if (!p.has("mac")) throw io::ParamError("mac", "every DeviceNet device needs its mac (0..63)");
  if (e.mac == cfg_.mac) throw io::ParamError("mac", "the device has the master's MAC ID");
  for (std::size_t i = 0; i < scanner_->size(); ++i)
    if (entries_[i].mac == e.mac)
      throw io::ParamError("mac", "MAC ID " + std::to_string(e.mac) + " is already used by '" +
                                      entries_[i].name + "'");
  // Up to 64 fragments of 7 bytes.
  in = p.get_int("input_bytes", in, 0, 448);
  out = p.get_int("output_bytes", out, 0, 448);
  if (in < 0 || out < 0)
    throw io::ParamError(in < 0 ? "input_bytes" : "output_bytes",
                         "a generic DeviceNet device needs input_bytes and output_bytes");
  e.input_size = static_cast<std::size_t>(in);
  e.output_size = static_cast<std::size_t>(out);
  if (p.has("vendor")) e.vendor = static_cast<std::uint16_t>(p.get_int("vendor", 0, 0, 65535));
  if (p.has("product")) e.product = static_cast<std::uint16_t>(p.get_int("product", 0, 0, 65535));
  if (p.get_bool("check_identity", true) == false) e.vendor = e.product = std::nullopt;
  e.epr = p.get_time("epr", e.epr, milliseconds(1), milliseconds(65535));
  if (e.epr < cfg_.poll_cycle)
    throw io::ParamError("epr", "epr must be at least the plugin's poll_cycle");
  const std::string io_type = p.get_string("io", "poll");
  if (io_type != "poll")
    throw io::ParamError("io",
                         "io must be poll (bit-strobe and change-of-state are not "
                         "implemented; the VF66B and the PR1721/34 support poll only)");
  e.startup = parse_startup_writes(p.get_string("startup", ""));
  p.reject_unknown();
  entries_.push_back(e);
  scanner_->add(e);
  return {e.input_size, e.output_size};
}

void DeviceNetPlugin::open() {
  if (bus_) return;
  try {
    if (host_hub_) {
      const std::string rest = bus_spec_.substr(4);
      const auto colon = rest.rfind(':');
      hub_ = std::make_unique<can::UdpHub>(
          rest.substr(0, colon), static_cast<std::uint16_t>(std::stoi(rest.substr(colon + 1))));
    }
    bus_ = can::open_bus(bus_spec_);
    if (!pcap_path_.empty()) pcap_ = std::make_unique<can::PcapWriter>(pcap_path_);
  } catch (const can::BusError& e) {
    throw io::PluginStartError(std::string("devicenet: ") + e.what());
  }
  tap_ = std::make_unique<CapturingBus>(*bus_, pcap_.get());
  scanner_->attach(tap_.get());
}

void DeviceNetPlugin::start(io::ClockMode mode) {
  open();
  if (mode == io::ClockMode::RealTime && !running_.exchange(true))
    thread_ = std::thread([this] {
      // The bus thread failing leaves the slaves unpolled: their devices
      // go to Fault (Plugin::fail), the slaves' own timeouts stop them.
      run_guarded(
          "devicenet bus thread", [this] { run_realtime(); },
          [this](std::string_view what) { fail("devicenet bus thread", what, entries_.size()); });
    });
}

void DeviceNetPlugin::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
  if (failed()) return;  // whatever broke the bus thread may break the flush too
  if (pcap_) pcap_->flush();
}

void DeviceNetPlugin::tick(TIME now) {
  std::lock_guard<std::mutex> lock(mutex_);
  tap_->set_time(now);
  scanner_->tick(now);
  // The controller's state from its error frames (SocketCAN): error-passive
  // warns before bus-off, bus-off takes every device with it.
  const can::BusState s = bus_->state();
  if (s != bus_state_) {
    bus_state_ = s;
    if (log_) std::fprintf(stderr, "devicenet: bus %s\n", can::to_string(s));
  }
}

void DeviceNetPlugin::step(TIME now, TIME) {
  if (tap_) tick(now);
}

void DeviceNetPlugin::run_realtime() {
  auto mono = [] {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  };
  const std::int64_t t0 = mono();
  while (running_.load(std::memory_order_relaxed)) {
    tick(TIME(mono() - t0));
    // Wake on the next frame, or after 1 ms for the timers (poll cycle,
    // timeouts); with no descriptor (in-memory bus) a plain 1 ms wait.
    pollfd pfd{tap_->fd(), POLLIN, 0};
    if (pfd.fd >= 0) {
      (void)poll(&pfd, 1, 1);
    } else {
      timespec ts{0, 1'000'000};
      nanosleep(&ts, nullptr);
    }
  }
}

void DeviceNetPlugin::latch_inputs(std::size_t device, std::span<std::uint8_t> dst) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto src = scanner_->inputs(device);
  std::memcpy(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

void DeviceNetPlugin::publish_outputs(std::size_t device, std::span<const std::uint8_t> src) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto dst = scanner_->outputs(device);
  std::memcpy(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

std::string DeviceNetPlugin::diagnostics(std::size_t device) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string s = scanner_->diagnostics(device);
  if (bus_) {
    const auto& c = bus_->counters();
    s += "; bus " + std::string(can::to_string(bus_->state())) + " tx " + std::to_string(c.tx) +
         " rx " + std::to_string(c.rx) + " rx-bad " + std::to_string(c.rx_bad) + " tx-dropped " +
         std::to_string(c.tx_dropped) + " error-frames " + std::to_string(c.error_frames) +
         " bus-bad-frames " + std::to_string(scanner_->bad_frames());
  }
  if (scanner_->duplicate_mac()) s += "; DUPLICATE MAC ID: the master stays off the bus";
  return s;
}

PLC_REGISTER_PLUGIN("devicenet", DeviceNetPlugin)

}  // namespace plc::devicenet
