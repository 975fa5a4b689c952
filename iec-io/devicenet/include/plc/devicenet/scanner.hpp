// The DeviceNet master (scanner) without threads or a clock of its own: the
// plugin (devicenet_plugin.hpp) calls tick() from its bus thread in real
// time, or from step() in virtual time; tests call it directly.
//
// Start-up: the duplicate MAC ID check for the master's own MAC (request,
// wait, request, wait; any answer = another node owns it, the scanner goes
// to Fault). Then per device of the scan list:
//   Release (clears what an earlier master session left) -> Allocate
//   explicit + poll on the Group 2 Only unconnected port (retried every
//   `retry`) -> optional vendor/product checks (Identity attrs 1, 3) ->
//   produced/consumed size checks (Connection 2 attrs 7, 8) -> EPR
//   (Connection 2 attr 9) -> start-up attribute writes -> Online: polled
//   I/O every poll cycle, FBs' explicit requests (the record path,
//   explicit_message.hpp), and a keep-alive Get on the explicit connection
//   so its 4 x EPR watchdog never fires.
// Device loss: no complete poll response of the configured size within
// 4 x EPR, or bus-off. Its inputs go to zero, its link Offline (FBs report
// it), and after `retry` the scanner allocates it again by itself.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plc/can/bus.hpp"
#include "plc/devicenet/explicit_frame.hpp"
#include "plc/io/device_link.hpp"
#include "plc/types.hpp"

namespace plc::devicenet {

struct AttributeWrite {
  std::uint8_t cls = 0, instance = 0, attribute = 0;
  std::vector<std::uint8_t> data;
};

struct ScanEntry {
  std::string name;
  std::uint8_t mac = 0;
  std::optional<std::uint16_t> vendor;       // Identity attr 1 must match
  std::optional<std::uint16_t> product;      // Identity attr 3 must match
  std::size_t input_size = 0;                // produced by the slave (%I)
  std::size_t output_size = 0;               // consumed by the slave (%Q)
  TIME epr = std::chrono::milliseconds(50);  // expected packet rate of the poll connection
  std::vector<AttributeWrite> startup;
};

struct ScannerConfig {
  std::uint8_t mac = 0;
  std::uint16_t vendor = 0xFFFF;      // in our duplicate MAC check messages
  std::uint32_t serial = 0x50C0FFEE;  // likewise
  TIME poll_cycle = std::chrono::milliseconds(10);
  TIME dup_mac_wait = std::chrono::seconds(1);
  TIME retry = std::chrono::seconds(1);
  TIME explicit_timeout = std::chrono::milliseconds(500);
  TIME keep_alive = std::chrono::milliseconds(1000);  // explicit connection (EPR 2500 ms)
};

enum class ScanState : std::uint8_t {
  Waiting,      // master not on line yet, or waiting to retry
  Releasing,    // Release sent
  Allocating,   // Allocate sent on the unconnected port
  Configuring,  // checks, EPR and start-up writes on the explicit connection
  Online,       // polled I/O running
  Fault,        // identity or size check failed (retried as Waiting)
};
const char* to_string(ScanState s);

struct DeviceCounters {
  std::uint64_t polls = 0, responses = 0, losses = 0, allocations = 0, allocation_errors = 0,
                bad_frames = 0, wrong_size = 0, explicit_ok = 0, explicit_errors = 0,
                explicit_timeouts = 0;
  // Frames to or for this device that the interface did not take (down,
  // its queue full): such a message never reached the wire.
  std::uint64_t send_failures = 0;
};

class Scanner {
 public:
  Scanner(const ScannerConfig& cfg, can::Bus* bus);
  // The bus may be attached after the devices are added (before tick()).
  void attach(can::Bus* bus) { bus_ = bus; }
  // Adds a device; its index is the number of devices added before it.
  std::size_t add(const ScanEntry& e);

  // Reads the bus, runs every state machine and sends what is due.
  void tick(TIME now);

  // Cyclic data (callers synchronise: the plugin holds its mutex).
  std::span<const std::uint8_t> inputs(std::size_t d) const { return devices_[d]->in; }
  std::span<std::uint8_t> outputs(std::size_t d) { return devices_[d]->out; }
  io::DeviceLink& link(std::size_t d) { return devices_[d]->link; }
  [[nodiscard]] ScanState state(std::size_t d) const { return devices_[d]->state; }
  [[nodiscard]] const DeviceCounters& counters(std::size_t d) const {
    return devices_[d]->counters;
  }
  [[nodiscard]] std::string diagnostics(std::size_t d) const;
  [[nodiscard]] bool on_line() const { return phase_ == Phase::Online; }
  [[nodiscard]] bool duplicate_mac() const { return phase_ == Phase::Duplicate; }
  [[nodiscard]] std::size_t size() const { return devices_.size(); }
  // Malformed frames that belong to no device: an invalid identifier
  // (0x7F0..0x7FF), a duplicate MAC ID message for our MAC of the wrong size.
  [[nodiscard]] std::uint64_t bad_frames() const { return bad_frames_; }
  // Called on every change of a device's state (the plugin logs them).
  std::function<void(std::size_t device, ScanState state, const std::string& why)> on_change;

 private:
  enum class Phase : std::uint8_t { Start, DupMacCheck, Online, Duplicate };
  enum class Step : std::uint8_t {
    None,
    Release,
    Allocate,
    Vendor,
    Product,
    Produced,
    Consumed,
    Epr,
    Startup,
    KeepAlive,
    Record
  };
  struct Device {
    ScanEntry cfg;
    ScanState state = ScanState::Waiting;
    std::vector<std::uint8_t> in, out;
    io::DeviceLink link;
    DeviceCounters counters;
    TIME next_try{0};
    TIME last_response{0};
    TIME last_explicit{0};
    std::string last_error;
    // The one explicit transaction in flight.
    Step step = Step::None;
    std::size_t startup_index = 0;
    io::RecordRequest* record = nullptr;
    TIME deadline{0};
    ExplicitFrames tx;
    std::size_t tx_next = 0;
    ExplicitReassembler rx;
    IoReassembler poll_rx;
  };

  void on_frame(const can::Frame& f, TIME now);
  void on_explicit_response(Device& d, const can::Frame& f, TIME now);
  void on_message(Device& d, std::span<const std::uint8_t> msg, TIME now);
  void on_poll_response(Device& d, const can::Frame& f, TIME now);
  void run_device(Device& d, TIME now);
  void begin(Device& d, Step s, std::span<const std::uint8_t> msg, bool unconnected, TIME now);
  void next_config_step(Device& d, TIME now);
  void lose(Device& d, TIME now, const std::string& why);
  void changed(const Device& d);
  void fail_record(Device& d, io::RecordError e, std::uint16_t code = 0);
  void send_poll(Device& d);
  // Sends a frame of device d's traffic; counts a failure (send_failures).
  bool send(Device& d, const can::Frame& f);
  void allocate(Device& d, TIME now);

  ScannerConfig cfg_;
  can::Bus* bus_;
  std::vector<std::unique_ptr<Device>> devices_;
  std::array<std::int16_t, 64> by_mac_{};
  Phase phase_ = Phase::Start;
  int dup_sent_ = 0;
  TIME dup_next_{0};
  TIME next_poll_{0};
  std::uint64_t bad_frames_ = 0;
};

}  // namespace plc::devicenet
