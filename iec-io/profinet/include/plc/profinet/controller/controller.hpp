// The PROFINET IO controller without threads or a clock of its own: the
// plugin (profinet_plugin.hpp) calls poll() from its cyclic thread in real
// time, or from step() in virtual time; tests call it directly over the
// in-memory links, in lockstep with PnDevice (deterministic).
//
// Bring-up of one AR per device, in the order a device expects
// (fieldbus-masters.md §1):
//   DCP Identify by NameOfStation (optionally DCP Set NameOfStation / IP
//   first) -> RPC Connect (ARBlockReq, input + output IOCRBlockReq,
//   AlarmCRBlockReq, ExpectedSubmoduleBlockReq built from the device's
//   DeviceDescription) -> output frames start at once, IOPS/IOCS good ->
//   Write of the start-up records (one MultipleWrite 0xE040) -> PrmEnd
//   (our UDP 34964 port is bound from the start, so the device's
//   ApplicationReady always finds it) -> answer ApplicationReady with 0x8112
//   DONE -> Online once a valid input frame has arrived too.
// Online: one RT_CLASS_1 output frame per send interval (send clock x
// reduction ratio), input frames checked as p-net checks ours (source MAC,
// exact length, TransferStatus 0, DataValid, cycle counter advancing), the
// data-hold watchdog (data-hold factor x interval without a valid input
// frame -> lost: inputs zero, link Offline, pending records NotReachable,
// reconnect after `retry`), record read/write (the FBs' RecordRequests over
// RPC Read/Write), alarms (DATA-RTA answered with ACK-RTA, then AlarmAck).
// stop(): Release of every AR.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "plc/io/device_link.hpp"
#include "plc/profinet/controller/device_counters.hpp"
#include "plc/profinet/description/device_description.hpp"
#include "plc/profinet/link/ethernet_port.hpp"
#include "plc/profinet/link/udp_port.hpp"
#include "plc/types.hpp"

namespace plc::profinet {

struct RpcPdu;
struct NdrResponse;
enum class RpcCall : std::uint8_t;

struct ControllerConfig {
  std::string station_name = "softplc";  // CMInitiatorStationName
  std::uint16_t vendor_id = 0x0000;      // in our CMInitiatorObjectUUID
  std::uint16_t device_id = 0x0000;
  std::uint16_t send_clock_factor = 32;               // x 31.25 us: 32 = 1 ms
  std::uint16_t reduction_ratio = 1;                  // send interval = send clock x ratio
  std::uint16_t data_hold_factor = 3;                 // watchdog: factor x send interval
  TIME dcp_timeout = std::chrono::milliseconds(500);  // identify / set answer window
  TIME rpc_timeout = std::chrono::milliseconds(500);  // one RPC request
  TIME ready_timeout = std::chrono::seconds(5);       // PrmEnd -> ApplicationReady
  TIME retry = std::chrono::seconds(1);               // before a lost/refused device is tried again
  TIME record_timeout = std::chrono::seconds(2);
  [[nodiscard]] TIME send_interval() const {
    return std::chrono::nanoseconds(31250) * send_clock_factor * reduction_ratio;
  }
};

struct ControllerDevice {
  std::string name;        // the cell's device name (logs)
  DeviceDescription desc;  // station name, IP, slots
  bool set_name = false;   // DCP Set NameOfStation to the device with `mac` first
  bool set_ip = false;     // DCP Set IP (desc.ip) before connecting
  Mac mac{};               // for set_name: the device to name (as the TIA "assign name")
  // Where the FBs' record requests go (RecordRequest carries only the
  // index): by default the first submodule with IO data.
  std::uint32_t record_api = 0;
  std::uint16_t record_slot = 0, record_subslot = 0;
  bool record_target_given = false;
};

enum class ArState : std::uint8_t {
  Waiting,      // not started, or waiting to retry
  Identifying,  // DCP Identify (name) sent
  Naming,       // DCP Set NameOfStation / IP sent
  Connecting,   // RPC Connect sent
  Writing,      // start-up records (MultipleWrite) sent
  PrmEnd,       // PrmEnd sent
  AwaitReady,   // waiting for the device's ApplicationReady
  Online,       // data exchange
  Fault,        // refused (Connect error, identity): retried after `retry`
};
const char* to_string(ArState s);

class Controller {
 public:
  Controller(const ControllerConfig& cfg, EthernetPort* eth, UdpPort* udp);
  ~Controller();
  Controller(const Controller&) = delete;
  Controller& operator=(const Controller&) = delete;
  // Ports may be attached after the devices are added (before poll()).
  void attach(EthernetPort* eth, UdpPort* udp);
  // Adds a device; its index is the number of devices added before it.
  // Throws std::invalid_argument when the description cannot be connected
  // (no IO submodule, data too long for one frame, ...).
  std::size_t add(const ControllerDevice& d);

  // Receives what the ports hold, runs every device's state machine and
  // sends what is due (cyclic frames whose send time has come).
  void poll(TIME now);
  // When poll() next has something to send (the earliest cyclic frame due
  // or timer); the real-time thread sleeps until then.
  [[nodiscard]] TIME next_due() const { return next_due_; }
  // Sends a Release for every AR (stop); answers are not waited for.
  void release_all(TIME now);
  // Release requests still waiting for their answer.
  [[nodiscard]] bool releasing() const;

  // Cyclic data (callers synchronise: the plugin holds its mutex). Inputs
  // are zero while the device is not Online.
  // Inline: the plugin copies them every scan.
  [[nodiscard]] std::span<const std::uint8_t> inputs(std::size_t d) const { return in_views_[d]; }
  [[nodiscard]] std::span<std::uint8_t> outputs(std::size_t d) { return out_views_[d]; }
  io::DeviceLink& link(std::size_t d);
  [[nodiscard]] ArState state(std::size_t d) const;
  [[nodiscard]] const DeviceCounters& counters(std::size_t d) const;
  [[nodiscard]] std::string diagnostics(std::size_t d) const;
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] std::uint64_t unmatched_frames() const { return unmatched_; }
  // Called on every change to/from Online and on faults (the plugin logs).
  std::function<void(std::size_t device, ArState state, const std::string& why)> on_change;

  struct Device;  // controller_device.hpp (the per-AR state)

 private:
  inline void on_ethernet(std::span<const std::uint8_t> frame, TIME now);  // inline in poll()
  void on_acyclic(const PnFrameView& v, TIME now);  // on_ethernet(): alarms, DCP
  void on_alarm(Device& d, std::uint16_t frame_id, std::span<const std::uint8_t> pdu, TIME now);
  void on_udp(std::span<const std::uint8_t> data, Ipv4 ip, std::uint16_t port, TIME now);
  void on_rpc_request(Device& d, const RpcPdu& pdu, Ipv4 ip, std::uint16_t port, TIME now);
  void on_rpc_response(Device& d, RpcCall call, const NdrResponse& res, TIME now);
  void run_device(Device& d, TIME now);
  void identify(Device& d, TIME now);
  void dcp_set(Device& d, TIME now, bool name);
  void connect(Device& d, TIME now);
  void write_startup(Device& d, TIME now);
  void prm_end(Device& d, TIME now);
  void release(Device& d, TIME now);
  void call(Device& d, RpcCall call, std::uint16_t opnum, std::span<const std::uint8_t> args,
            TIME now, TIME timeout);
  void start_cyclic(Device& d, TIME now);
  void stop_cyclic(Device& d);
  inline void send_cyclic(Device& d, TIME now);  // inline in poll()
  void drop_link(Device& d);
  void lose(Device& d, TIME now, const std::string& why);
  void fault(Device& d, TIME now, const std::string& why);
  void changed(const Device& d);

  ControllerConfig cfg_;
  EthernetPort* eth_;
  Mac mac_{};  // eth_'s, read once (every received frame is checked against it)
  UdpPort* udp_;
  // The ports' queued_count(), read once: a poll skips a port that holds
  // nothing without a call.
  const std::atomic<std::size_t>* eth_queued_ = nullptr;
  const std::atomic<std::size_t>* udp_queued_ = nullptr;
  std::vector<std::unique_ptr<Device>> devices_;
  // Each device's in and out (its staging buffers), taken in add(): sized
  // there and never again, they stay where they are.
  std::vector<std::span<const std::uint8_t>> in_views_;
  std::vector<std::span<std::uint8_t>> out_views_;
  std::vector<std::uint8_t> rx_;  // one frame / datagram
  // An RPC call's args (record requests), NDR body and datagram, built in
  // place (the wire *_to() encoders): reused, they allocate only until they
  // have grown to the longest call, so a record exchange allocates nothing.
  std::vector<std::uint8_t> call_args_, call_body_, call_dgram_;
  std::uint32_t next_ar_ = 1;  // AR UUIDs and session keys
  std::uint16_t next_frame_id_ = 0xC000;
  TIME next_due_{0};
  std::uint64_t unmatched_ = 0;  // frames for no AR of ours (other traffic on the wire)
};

}  // namespace plc::profinet
