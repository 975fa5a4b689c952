#include "plc/io/sim_plugin.hpp"

#include <time.h>

#include <algorithm>
#include <cstring>

#include "plc/io/device_peers.hpp"
#include "plc/thread_guard.hpp"

namespace plc::io {

SimPlugin::~SimPlugin() { stop(); }

void SimPlugin::configure(const ModelParams& params) {
  // Real time only. Below 10 us the stepping thread would keep a core busy;
  // above 1 s devices would answer too rarely for any bus.
  step_ = params.get_time("step", step_, std::chrono::microseconds(10), std::chrono::seconds(1));
  params.reject_unknown();
}

DeviceSizes SimPlugin::add_device(const DeviceSpec& spec) {
  const DeviceModelFactory* f = DeviceModelRegistry::instance().find(spec.model);
  if (!f) {
    std::string known;
    for (const auto& n : DeviceModelRegistry::instance().names())
      known += (known.empty() ? "" : ", ") + n;
    throw ParamError("model", "unknown device model '" + spec.model + "' (known: " + known + ")");
  }
  // The link fault switch is the plugin's, not the model's: read (and so
  // marked used) before the model rejects keys it does not know.
  constexpr TIME kForever = std::chrono::hours(24 * 365 * 100);
  TIME down_at{-1};
  TIME down_for = kForever;
  if (spec.params.has("link_down_at"))
    down_at = spec.params.get_time("link_down_at", TIME(0), TIME(0), kForever);
  if (spec.params.has("link_down_for")) {
    if (!spec.params.has("link_down_at"))
      throw ParamError("link_down_for",
                       "link_down_for needs link_down_at (when the link goes down)");
    down_for = spec.params.get_time("link_down_for", kForever, TIME(1), kForever);
  }
  auto model = (*f)(spec.params);
  // A coupled model (plc/io/device_peers.hpp) sees the devices added before
  // it: step() runs them first, so it reads what they delivered this step.
  if (auto* coupled = dynamic_cast<PeerCoupledModel*>(model.get())) {
    class Earlier final : public DevicePeers {
     public:
      explicit Earlier(SimPlugin& p) : p_(p) {}
      std::optional<Peer> find(std::string_view name) const override {
        for (std::size_t i = 0; i < p_.names_.size(); ++i)
          if (p_.names_[i] == name)
            return Peer{p_.devices_[i]->inputs(), p_.devices_[i]->outputs()};
        return std::nullopt;
      }
      std::vector<std::string> names() const override { return p_.names_; }

     private:
      SimPlugin& p_;
    };
    coupled->bind_peers(Earlier(*this));
  }
  devices_.push_back(std::make_unique<SimDevice>(std::move(model)));
  devices_.back()->set_link_down(down_at, down_for);
  names_.push_back(spec.name);
  return {devices_.back()->inputs().size(), devices_.back()->outputs().size()};
}

void SimPlugin::start(ClockMode mode) {
  locking_ = mode == ClockMode::RealTime;
  if (mode == ClockMode::RealTime && !running_.exchange(true)) {
    thread_ = std::thread([this] {
      run_guarded(
          "sim plugin", [this] { run_realtime(); },
          [this](std::string_view what) { fail("sim plugin", what, devices_.size()); });
    });
  }
}

void SimPlugin::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
}

void SimPlugin::step(TIME now, TIME dt) {
  for (auto& d : devices_) d->step(now, dt);
}

// Steps on a fixed grid, but hands the models the time that really passed
// (now = time since start, dt = since the previous step): a step that comes
// late, because the machine or a lock held us up, shows as a longer dt, as a
// late frame would on a real bus.
void SimPlugin::run_realtime() {
  auto mono = [] {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  };
  const std::int64_t step_ns = step_.count();
  const std::int64_t t0 = mono();
  std::int64_t prev = t0, next = t0;
  while (running_.load(std::memory_order_relaxed)) {
    const std::int64_t now = mono();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      step(TIME(now - t0), TIME(now - prev));
    }
    prev = now;
    next += step_ns;
    if (next < now) next = now + step_ns;  // fell behind: no burst of catch-up steps
    timespec ts{static_cast<time_t>(next / 1'000'000'000), static_cast<long>(next % 1'000'000'000)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
  }
}

namespace {
// A device may have no inputs or no outputs (a plant that only writes into
// another device): an empty span's data() is null, which memcpy must not
// get even for 0 bytes (UBSan); copy_n takes it.
void copy_bytes(std::span<const std::uint8_t> src, std::span<std::uint8_t> dst) {
  std::copy_n(src.data(), std::min(src.size(), dst.size()), dst.data());
}
}  // namespace

void SimPlugin::latch_inputs(std::size_t device, std::span<std::uint8_t> dst) {
  auto src = devices_[device]->inputs();
  if (!locking_) {
    copy_bytes(src, dst);
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  copy_bytes(src, dst);
}

void SimPlugin::publish_outputs(std::size_t device, std::span<const std::uint8_t> src) {
  auto dst = devices_[device]->outputs();
  if (!locking_) {
    copy_bytes(src, dst);
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  copy_bytes(src, dst);
}

std::optional<Plugin::DirectIo> SimPlugin::direct_io(std::size_t device) {
  if (locking_) return std::nullopt;
  return DirectIo{devices_[device]->inputs(), devices_[device]->outputs()};
}

SimDevice* SimPlugin::device(const std::string& name) {
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return devices_[i].get();
  return nullptr;
}

PLC_REGISTER_PLUGIN("sim", SimPlugin)

}  // namespace plc::io
