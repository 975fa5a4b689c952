#include "plc/profinet/controller/profinet_plugin.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "plc/io/device_model.hpp"
#include "plc/profinet/controller/device_params.hpp"
#include "plc/profinet/device/pn_device.hpp"
#include "plc/profinet/link/open_link.hpp"
#include "plc/profinet/wire/cyclic.hpp"
#include "plc/realtime_thread.hpp"
#include "plc/thread_guard.hpp"

namespace plc::profinet {

namespace {
using std::chrono::milliseconds;
using std::chrono::seconds;
}  // namespace

ProfinetPlugin::ProfinetPlugin() = default;
ProfinetPlugin::~ProfinetPlugin() { stop(); }

void ProfinetPlugin::configure(const io::ModelParams& p) {
  interface_ = p.get_string("interface", "");
  if (interface_.empty())
    throw io::ParamError("interface", "the profinet plugin needs interface: IFACE or mem:NAME");
  const std::string ip = p.get_string("ip", "192.168.0.1");
  const auto parsed = parse_ipv4(ip);
  if (!parsed) throw io::ParamError("ip", "'" + ip + "' is not an IPv4 address (a.b.c.d)");
  ip_ = *parsed;
  cfg_.station_name = p.get_string("station_name", cfg_.station_name);
  if (const std::string why = station_name_problem(cfg_.station_name); !why.empty())
    throw io::ParamError("station_name", why);
  // Send clock: a power of two x 31.25 us from 250 us to 4 ms (RT_CLASS_1
  // SendClockFactor 8..128; fieldbus-masters.md §1 item 2).
  const TIME clock =
      p.get_time("send_clock", milliseconds(1), std::chrono::microseconds(250), milliseconds(4));
  const auto factor = clock.count() / 31250;
  if (factor * 31250 != clock.count() || (factor & (factor - 1)) != 0)
    throw io::ParamError("send_clock",
                         "send_clock must be 250us, 500us, 1ms, 2ms or 4ms (a power of two "
                         "times 31.25 us)");
  cfg_.send_clock_factor = static_cast<std::uint16_t>(factor);
  cfg_.reduction_ratio = static_cast<std::uint16_t>(p.get_int("reduction_ratio", 1, 1, 512));
  cfg_.data_hold_factor = static_cast<std::uint16_t>(p.get_int("data_hold_factor", 3, 1, 0x1E00));
  cfg_.dcp_timeout = p.get_time("dcp_timeout", cfg_.dcp_timeout, milliseconds(1), seconds(10));
  cfg_.rpc_timeout = p.get_time("rpc_timeout", cfg_.rpc_timeout, milliseconds(1), seconds(60));
  cfg_.ready_timeout =
      p.get_time("ready_timeout", cfg_.ready_timeout, milliseconds(1), seconds(600));
  cfg_.retry = p.get_time("retry", cfg_.retry, milliseconds(10), seconds(60));
  cfg_.record_timeout =
      p.get_time("record_timeout", cfg_.record_timeout, milliseconds(1), seconds(60));
  simulate_ = p.get_bool("simulate", false);
  if (simulate_ && !is_memory_link(interface_))
    throw io::ParamError("simulate",
                         "simulate: true hosts the devices on an in-memory link: it needs "
                         "interface: mem:NAME");
  log_ = p.get_bool("log", true);
  priority_ = static_cast<int>(p.get_int("priority", 60, 1, 99));
  p.reject_unknown();
}

io::DeviceSizes ProfinetPlugin::add_device(const io::DeviceSpec& spec) {
  ControllerDevice d = device_from_params(spec.name, spec.model, spec.params);
  // The device's own model (a registered one): its parameters are checked
  // here, its cyclic sizes must be the description's, and with simulate it
  // is the device behind the simulated PnDevice.
  io::ModelParams model_params = device_model_params(spec.params);
  std::unique_ptr<io::DeviceModel> model;
  if (const auto* f = io::DeviceModelRegistry::instance().find(spec.model)) {
    model = (*f)(model_params);
    if (model->input_size() != d.desc.input_size() || model->output_size() != d.desc.output_size())
      throw io::ParamError("", "the description's IO data (" + std::to_string(d.desc.input_size()) +
                                   " in, " + std::to_string(d.desc.output_size()) +
                                   " out) is not the model's (" +
                                   std::to_string(model->input_size()) + " in, " +
                                   std::to_string(model->output_size()) + " out)");
  } else if (simulate_) {
    throw io::ParamError("",
                         "simulate: true needs a device model, and '" + spec.model + "' is none");
  } else {
    model_params.reject_unknown();
  }
  for (const auto& e : entries_) {
    if (e.desc.station_name == d.desc.station_name)
      throw io::ParamError("station_name", "station name '" + d.desc.station_name +
                                               "' is already used by device '" + e.name + "'");
    if (e.desc.ip == d.desc.ip)
      throw io::ParamError(
          "ip", "IP " + to_string(d.desc.ip) + " is already used by device '" + e.name + "'");
  }
  if (d.desc.ip == ip_)
    throw io::ParamError("ip", "the device has the controller's IP " + to_string(ip_));
  if (!controller_) controller_ = std::make_unique<Controller>(cfg_, nullptr, nullptr);
  controller_->add(d);  // throws std::invalid_argument: not connectable
  entries_.push_back(d);
  sim_models_.push_back(simulate_ ? std::move(model) : nullptr);
  return {d.desc.input_size(), d.desc.output_size()};
}

void ProfinetPlugin::open() {
  if (eth_) return;
  if (!controller_) controller_ = std::make_unique<Controller>(cfg_, nullptr, nullptr);
  try {
    eth_ = open_ethernet(interface_);
    udp_ = open_udp(interface_, ip_, kPnioRpcPort);
    if (simulate_) {
      for (std::size_t i = 0; i < entries_.size(); ++i) {
        sim_eth_.push_back(open_ethernet(interface_));
        PnDeviceConfig dc;
        dc.description = entries_[i].desc;
        const std::string spec = interface_;
        sim_.push_back(std::make_unique<PnDevice>(
            dc, std::move(sim_models_[i]), *sim_eth_.back(),
            [spec](Ipv4 ip) { return open_udp(spec, ip, kPnioRpcPort); }));
      }
    }
  } catch (const LinkError& e) {
    throw io::PluginStartError(std::string("profinet: ") + e.what());
  }
  controller_->attach(eth_.get(), udp_.get());
  controller_->on_change = [this](std::size_t d, ArState st, const std::string& why) {
    if (!log_) return;
    std::fprintf(stderr, "profinet: %s (%s): %s%s%s\n", entries_[d].name.c_str(),
                 entries_[d].desc.station_name.c_str(), to_string(st), why.empty() ? "" : ": ",
                 why.c_str());
  };
}

void ProfinetPlugin::start(io::ClockMode mode) {
  open();
  mode_ = mode;
  // Virtual time: the runtime's one scan thread steps every plugin, so the
  // controller and the simulated devices (and any other plugin's ports on
  // the same mem: link) are driven by that thread alone: the in-memory link
  // needs no lock. Real time keeps it (the cyclic thread, stop()'s caller).
  single_threaded_link_ = mode == io::ClockMode::Virtual && is_memory_link(interface_);
  if (single_threaded_link_) set_memory_link_single_threaded(interface_, true);
  if (mode == io::ClockMode::RealTime && !running_.exchange(true))
    thread_ = std::thread([this] {
      // Its devices go to Fault (Plugin::fail); without cyclic frames
      // their own watchdogs put their outputs to the substitute values.
      run_guarded(
          "profinet cyclic thread", [this] { run_realtime(); },
          [this](std::string_view what) { fail("profinet cyclic thread", what, entries_.size()); });
    });
}

void ProfinetPlugin::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
  // The link locks again from here on: whoever uses it next may be
  // another thread (the locked path is right for any use).
  if (single_threaded_link_) set_memory_link_single_threaded(interface_, false);
  single_threaded_link_ = false;
  // A failed cyclic thread: no release either (what broke it may break it).
  if (!controller_ || !eth_ || failed()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  // Release every AR. The answers are read for a bounded time (they end
  // the device's AR cleanly; nothing depends on them here).
  controller_->release_all(last_now_);
  if (mode_ == io::ClockMode::Virtual) {
    for (int i = 0; i < 3; ++i) {
      last_now_ += cfg_.send_interval();
      for (auto& s : sim_) s->poll(last_now_);
      controller_->poll(last_now_);
    }
  } else {
    const std::int64_t end = mono_ns() + 100'000'000;
    TIME now = last_now_;
    for (int i = 0; i < 100 && mono_ns() < end; ++i) {
      now += milliseconds(1);
      for (auto& s : sim_) s->poll(now);
      controller_->poll(now);
      if (!controller_->releasing()) break;
      sleep_until_ns(mono_ns() + 1'000'000);
    }
  }
}

namespace {
// Holds ProfinetPlugin's step lock (a ticket lock: step_next_ hands out
// tickets, step_serving_ says whose turn it is) while it lives. A waiter
// yields: the holder is a diagnostics() call or a step, both short.
class StepLock {
 public:
  StepLock(std::atomic<std::uint32_t>& next, std::atomic<std::uint32_t>& serving)
      : serving_(serving), ticket_(next.fetch_add(1, std::memory_order_relaxed)) {
    while (serving_.load(std::memory_order_acquire) != ticket_) std::this_thread::yield();
  }
  ~StepLock() { serving_.store(ticket_ + 1, std::memory_order_release); }
  StepLock(const StepLock&) = delete;
  StepLock& operator=(const StepLock&) = delete;

 private:
  std::atomic<std::uint32_t>& serving_;
  const std::uint32_t ticket_;
};
}  // namespace

[[gnu::always_inline]] inline void ProfinetPlugin::run_tick(TIME now) {
  last_now_ = now;
  controller_->poll(now);
  if (sim_.empty()) return;
  // Simulated devices: they take the outputs just sent, answer, and the
  // controller reads the answers at once, so FBs see a device's inputs one
  // scan after their outputs, as over the sim plugin.
  for (auto& s : sim_) s->poll(now);
  controller_->poll(now);
}

// Real time: the cyclic thread's tick excludes the scan's latch/publish
// (mutex_). Virtual time: the scan thread is the only one that steps, so
// only diagnostics() needs keeping out (the step lock).
void ProfinetPlugin::tick(TIME now) {
  if (mode_ == io::ClockMode::RealTime) return tick_locked(now);
  StepLock hold(step_next_, step_serving_);
  run_tick(now);
}

void ProfinetPlugin::tick_locked(TIME now) {
  std::lock_guard<std::mutex> lock(mutex_);
  run_tick(now);
}

void ProfinetPlugin::step(TIME now, TIME) {
  if (eth_) tick(now);
}

void ProfinetPlugin::run_realtime() {
  if (const int rc = set_fifo_priority(priority_); rc != 0 && log_)
    warn_fifo_refused("profinet", rc, "the cyclic thread runs at normal priority");
  const std::int64_t period = std::chrono::nanoseconds(31250 * cfg_.send_clock_factor).count();
  const std::int64_t t0 = mono_ns();
  std::int64_t k = 0;
  while (running_.load(std::memory_order_relaxed)) {
    const std::int64_t release = t0 + k * period;
    sleep_until_ns(release);
    const std::int64_t woke = mono_ns();
    tick(TIME(woke - t0));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const std::int64_t late = woke - release;
      ++wake_.wakes;
      wake_.sum_ns += late;
      wake_.max_ns = std::max(wake_.max_ns, late);
      // Overrun: skip to the next deadline still ahead (no burst).
      const std::int64_t behind = (mono_ns() - t0) / period;
      if (behind > k + 1) wake_.missed += static_cast<std::uint64_t>(behind - k - 1);
      k = std::max(k + 1, behind + 1);
    }
  }
}

// Virtual time: the scan's thread also runs the controller (step()), and
// diagnostics() from other threads reads neither staging buffer, so the
// copies need no mutex (as the sim plugin's).
// Real time takes the mutex in the *_locked() twins, out of line: the
// virtual-time copy then saves no registers for the lock.
void ProfinetPlugin::latch_inputs(std::size_t device, std::span<std::uint8_t> dst) {
  if (mode_ == io::ClockMode::RealTime) return latch_inputs_locked(device, dst);
  const auto src = controller_->inputs(device);
  copy_io_bytes(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

void ProfinetPlugin::latch_inputs_locked(std::size_t device, std::span<std::uint8_t> dst) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto src = controller_->inputs(device);
  copy_io_bytes(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

void ProfinetPlugin::publish_outputs(std::size_t device, std::span<const std::uint8_t> src) {
  if (mode_ == io::ClockMode::RealTime) return publish_outputs_locked(device, src);
  const auto dst = controller_->outputs(device);
  copy_io_bytes(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

void ProfinetPlugin::publish_outputs_locked(std::size_t device, std::span<const std::uint8_t> src) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto dst = controller_->outputs(device);
  copy_io_bytes(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

// Virtual time: latch_inputs()/publish_outputs() only copy from and to the
// controller's staging buffers, which add() sized once and which never
// move: the scan may copy them itself (the runtime takes them only if
// their sizes are the device's).
std::optional<io::Plugin::DirectIo> ProfinetPlugin::direct_io(std::size_t device) {
  if (mode_ != io::ClockMode::Virtual || !controller_ || device >= entries_.size())
    return std::nullopt;
  return DirectIo{controller_->inputs(device), controller_->outputs(device)};
}

PnDevice* ProfinetPlugin::simulated(std::size_t device) {
  return device < sim_.size() ? sim_[device].get() : nullptr;
}

WakeStats ProfinetPlugin::wake_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return wake_;
}

std::string ProfinetPlugin::diagnostics(std::size_t device) const {
  std::lock_guard<std::mutex> lock(mutex_);
  StepLock hold(step_next_, step_serving_);  // not mid-step in virtual time either
  std::string s = controller_->diagnostics(device);
  if (mode_ == io::ClockMode::RealTime && wake_.wakes > 0) {
    char b[160];
    std::snprintf(
        b, sizeof b, "; cyclic thread wake-ups %llu, late max %lld us avg %lld us, missed %llu",
        static_cast<unsigned long long>(wake_.wakes), static_cast<long long>(wake_.max_ns / 1000),
        static_cast<long long>(wake_.sum_ns / static_cast<std::int64_t>(wake_.wakes) / 1000),
        static_cast<unsigned long long>(wake_.missed));
    s += b;
  }
  return s;
}

PLC_REGISTER_PLUGIN("profinet", ProfinetPlugin)

}  // namespace plc::profinet
