// A PROFINET IO device (the device side of IEC 61158-6-10) in front of one
// DeviceModel, with no timing and no threads of its own: the host (pndevsim's
// real-time thread, or a test in virtual time over the Memory links) calls
// poll(now); the device reads what arrived, answers, runs its timers, sends
// its cyclic frame when due and steps the model once per send interval.
//
// What it does, in the order of an AR's life (fieldbus-masters.md §1):
//  * DCP: Identify All / by NameOfStation (answer delayed by
//    (MAC mod ResponseDelayFactor) x 10 ms), Get and Set NameOfStation / IP,
//    DeviceID, DeviceRole, DeviceOptions; Hello at start if asked.
//  * RPC Connect (opnum 0): reads and checks the blocks as p-net's
//    pf_cmrpc.c and pf_cmdev.c do (connect_check.hpp), refuses with the same
//    PNIO status and accepts what p-net accepts (a Warning event for each
//    point against IEC 61158-6-10 that p-net lets through); a
//    ModuleDiffBlock lists expected (sub)modules whose ident differs from
//    ours. RT_CLASS_1 and RT_CLASS_2 IOCRs alike (p-net runs both the same
//    way). Output frames start right after the Connect response.
//  * Write (opnum 3), single or MultipleWrite 0xE040: records go to the
//    model's write_record (the NORD F-parameters, the E1 parameter channel);
//    Read (opnum 2): the model's read_record.
//  * PrmEnd (Control, 0x0110 / ControlCommand PrmEnd) -> answer 0x8110,
//    then ApplicationReady (CControl 0x0112) to the controller's UDP 34964,
//    repeated every `app_ready_retry` until the controller answers 0x8112
//    DONE; data exchange begins once that answer and a valid output frame
//    are both there.
//  * Cyclic RT frames: our input frame every SendClockFactor x
//    ReductionRatio x 31.25 us to the controller's MAC (CycleCounter,
//    DataStatus 0x35, IOPS/IOCS good); controller frames are taken only as
//    p-net takes them (output_acceptance.hpp). The data-hold watchdog
//    (DataHoldFactor x send interval without a taken frame) drops the AR:
//    the model hears io_connection_lost() and gets zero outputs, and the
//    device waits for the next Connect.
//  * Alarms: raise_alarm() sends a DATA-RTA AlarmNotification (low priority
//    0xFE01 for diagnosis, high 0xFC01 for process alarms), repeated every
//    RTA timeout until the controller's ACK-RTA, then waits for its
//    AlarmAck; after RTARetries unanswered repeats the AR is aborted.
//  * Release (opnum 1): answered, AR closed.
// Outside an AR the model still steps (with zero outputs) every idle_step.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "plc/io/device_model.hpp"
#include "plc/profinet/description/device_description.hpp"
#include "plc/profinet/device/output_acceptance.hpp"
#include "plc/profinet/link/ethernet_port.hpp"
#include "plc/profinet/link/udp_port.hpp"
#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/dcp.hpp"
#include "plc/profinet/wire/ethernet.hpp"
#include "plc/profinet/wire/rpc.hpp"

namespace plc::profinet {

struct PnDeviceConfig {
  DeviceDescription description;  // station name, IP, idents, modules
  std::optional<Mac> mac;         // our source MAC; default: the port's
  std::chrono::nanoseconds idle_step = std::chrono::milliseconds(1);
  std::chrono::nanoseconds app_ready_retry = std::chrono::milliseconds(100);
  int app_ready_retries = 30;  // then the AR is aborted
  bool hello_at_start = false;
  bool vlan_tag = false;  // send cyclic frames with a priority-6 tag (VLAN 0)
};

// Fault switches (pndevsim: by config and at run time).
struct PnDeviceFaults {
  bool silent = false;                       // answer nothing, send nothing (a pulled plug)
  std::uint64_t drop_cyclic = 0;             // drop this many of our next cyclic frames
  bool drop_all_cyclic = false;              // ... or all of them while set
  std::chrono::nanoseconds delay_cyclic{0};  // send each cyclic frame this much late
  std::optional<PnioStatus> refuse_connect;  // answer every Connect with this status
};

enum class PnDeviceState : std::uint8_t {
  Idle,            // no AR: waiting for Connect
  Parameterizing,  // Connect answered, waiting for PrmEnd (records being written)
  AppReady,        // PrmEnd answered, ApplicationReady sent, waiting for DONE
  DataExchange,    // ApplicationReady confirmed, outputs taken
};
[[nodiscard]] const char* to_string(PnDeviceState s);

// Why an AR ended (pndevsim prints it).
enum class ArEnd : std::uint8_t {
  Released,
  DataHoldExpired,
  StartupTimeout,
  AlarmTimeout,
  AppReadyTimeout,
  Aborted
};
[[nodiscard]] const char* to_string(ArEnd e);

struct PnDeviceCounters {
  std::uint64_t dcp_requests = 0, dcp_answers = 0;
  std::uint64_t rpc_requests = 0, rpc_bad = 0;
  std::uint64_t connects = 0, connects_refused = 0;
  std::uint64_t writes = 0, reads = 0, record_errors = 0;
  std::uint64_t app_ready_sent = 0;
  std::uint64_t frames_sent = 0, frames_dropped_by_fault = 0;
  std::uint64_t frames_received = 0, frames_unknown = 0;  // to us / with an unknown FrameID
  std::uint64_t frames_bad = 0;                           // undecodable DCP, RTA or Ethernet header
  std::uint64_t data_hold_expired = 0;
  std::uint64_t alarms_sent = 0, alarm_repeats = 0, alarms_acked = 0;
  std::uint64_t releases = 0;
};

// What the device reports to its host (one line per change in pndevsim).
struct PnDeviceEvent {
  enum class Kind : std::uint8_t {
    Connected,
    Refused,
    DataExchange,
    Lost,
    Released,
    AlarmAcked,
    NameSet,
    IpSet,
    Warning  // an accepted Connect against IEC 61158-6-10 (connect_warnings())
  };
  Kind kind;
  PnioStatus status{};  // Refused: the status sent
  ArEnd end = ArEnd::Released;
  std::string text{};  // Warning: what and which clause
};
[[nodiscard]] std::string describe(const PnDeviceEvent& e);

enum class AlarmKind : std::uint8_t { Diagnosis, Process };

// DCP Identify answer delay: (MAC mod ResponseDelayFactor) x 10 ms, the
// MAC's last two bytes taken as the number; none for a factor of 0 or 1.
[[nodiscard]] std::chrono::nanoseconds dcp_response_delay(const Mac& mac, std::uint16_t factor);

class PnDevice {
 public:
  // `open_udp(ip)` opens the RPC port (UDP 34964) on `ip`; called at start
  // and after a DCP Set IP.
  using UdpOpener = std::function<std::unique_ptr<UdpPort>(Ipv4)>;
  using EventSink = std::function<void(const PnDeviceEvent&)>;

  PnDevice(PnDeviceConfig cfg, std::unique_ptr<io::DeviceModel> model, EthernetPort& eth,
           UdpOpener open_udp);
  ~PnDevice();
  PnDevice(const PnDevice&) = delete;
  PnDevice& operator=(const PnDevice&) = delete;

  void poll(std::chrono::nanoseconds now);
  // Hand one received frame to the device (hosts that share one port among
  // several devices read it themselves); poll() then does not read `eth`.
  void set_shared_port(bool shared) { shared_port_ = shared; }
  void on_frame(std::span<const std::uint8_t> frame, std::chrono::nanoseconds now);

  // Queues an alarm on the IO submodule (or slot/subslot given); false if no
  // AR is up or an alarm of that priority is still unacknowledged.
  bool raise_alarm(AlarmKind kind, std::uint16_t usi = 0x8000,
                   std::span<const std::uint8_t> data = {});

  void set_event_sink(EventSink s) { sink_ = std::move(s); }
  PnDeviceFaults& faults() { return faults_; }
  [[nodiscard]] PnDeviceState state() const { return state_; }
  [[nodiscard]] const PnDeviceCounters& counters() const { return counters_; }
  [[nodiscard]] const OutputAcceptance& acceptance() const { return accept_; }
  [[nodiscard]] const std::string& station_name() const { return station_name_; }
  [[nodiscard]] Ipv4 ip() const { return ip_; }
  [[nodiscard]] Mac mac() const { return mac_; }
  io::DeviceModel& model() { return *model_; }
  [[nodiscard]] std::string describe() const;

 private:
  struct Ar;
  struct PendingDcp {
    std::chrono::nanoseconds due{0};
    std::vector<std::uint8_t> frame;
  };
  struct Delayed {
    std::chrono::nanoseconds due{0};
    std::size_t length = 0;
    std::array<std::uint8_t, kMaxFrameLength> frame{};
  };

  // A pulled plug or a model that does not answer: asked for every frame
  // in and out, so inline.
  [[nodiscard]] bool quiet() const { return faults_.silent || !model_->answering(); }
  [[nodiscard]] DcpIdentity identity() const;
  inline void read_ethernet(std::chrono::nanoseconds now);  // inline in poll()
  // on_frame()'s body, inline in read_ethernet() (pn_device.cpp).
  inline void take_frame(std::span<const std::uint8_t> frame, std::chrono::nanoseconds now);
  void read_udp(std::chrono::nanoseconds now);
  void on_dcp(std::uint16_t frame_id, const Mac& src, std::span<const std::uint8_t> pdu,
              std::chrono::nanoseconds now);
  inline void on_cyclic(std::span<const std::uint8_t> frame, const PnFrameView& v,
                        std::chrono::nanoseconds now);
  void on_alarm(std::uint16_t frame_id, const Mac& src, std::span<const std::uint8_t> pdu,
                std::chrono::nanoseconds now);
  void on_rpc(std::span<const std::uint8_t> dgram, Ipv4 from, std::uint16_t port,
              std::chrono::nanoseconds now);
  void on_app_ready_response(const RpcPdu& pdu, std::chrono::nanoseconds now);
  PnioStatus serve_connect(std::span<const std::uint8_t> args, Ipv4 from,
                           std::vector<std::uint8_t>& out, std::chrono::nanoseconds now);
  std::optional<PnioStatus> setup_ar(const ConnectRequest& req, Ar& ar);
  PnioStatus serve_release(std::span<const std::uint8_t> args, std::vector<std::uint8_t>& out,
                           std::chrono::nanoseconds now);
  PnioStatus serve_control(std::span<const std::uint8_t> args, std::vector<std::uint8_t>& out,
                           std::chrono::nanoseconds now);
  PnioStatus serve_write(std::span<const std::uint8_t> args, std::vector<std::uint8_t>& out);
  PnioStatus serve_read(std::span<const std::uint8_t> args, std::uint16_t opnum,
                        std::vector<std::uint8_t>& out);
  PnioStatus write_one(const RecordRequestHeader& h, std::span<const std::uint8_t> data);
  [[nodiscard]] bool has_subslot(std::uint32_t api, std::uint16_t slot,
                                 std::uint16_t subslot) const;
  [[nodiscard]] bool ar_matches(const Uuid& ar_uuid) const;
  void maybe_enter_data_exchange(std::chrono::nanoseconds now);
  void timers(std::chrono::nanoseconds now);
  [[gnu::noinline]] void timers_due(std::chrono::nanoseconds now);  // the rest of timers()
  inline void send_cyclic(std::chrono::nanoseconds now);            // inline in poll()
  void build_cyclic_frame(Ar& ar);
  void flush_delayed(std::chrono::nanoseconds now);
  void step_model(std::chrono::nanoseconds now);
  void end_ar(ArEnd why, std::chrono::nanoseconds now);
  void emit(PnDeviceEvent e);
  void send_eth(std::span<const std::uint8_t> frame);
  void send_udp(Ipv4 ip, std::uint16_t port, std::span<const std::uint8_t> data);
  void set_udp(std::unique_ptr<UdpPort> port);  // udp_ and udp_queued_
  // A port's queued_count() reads 0 (an in-memory port holds nothing): a
  // poll skips it without a call.
  static bool may_hold(const std::atomic<std::size_t>* queued) {
    return !queued || queued->load(std::memory_order_relaxed) != 0;
  }

  PnDeviceConfig cfg_;
  std::unique_ptr<io::DeviceModel> model_;
  EthernetPort& eth_;
  UdpOpener open_udp_;
  std::unique_ptr<UdpPort> udp_;
  const std::atomic<std::size_t>* eth_queued_ = nullptr;  // eth_.queued_count()
  const std::atomic<std::size_t>* udp_queued_ = nullptr;  // udp_->queued_count()
  EventSink sink_;
  PnDeviceFaults faults_;
  PnDeviceCounters counters_;
  OutputAcceptance accept_;
  PnDeviceState state_ = PnDeviceState::Idle;
  bool shared_port_ = false;

  std::string station_name_;
  Ipv4 ip_;
  Ipv4 netmask_;
  Ipv4 gateway_;
  Mac mac_{};
  std::unique_ptr<Ar> ar_;
  std::vector<PendingDcp> dcp_out_;
  std::vector<std::uint8_t> from_plc_, to_plc_;
  std::array<std::uint8_t, kMaxFrameLength> rx_{};
  std::array<std::uint8_t, kMaxFrameLength> tx_{};  // our cyclic frame, its C_SDU built in place
  std::vector<Delayed> delayed_;
  std::size_t delayed_head_ = 0, delayed_tail_ = 0;
  std::vector<std::uint8_t> udp_rx_;
  // The last RPC answer, for a repeated request.
  std::vector<std::uint8_t> last_response_;
  // An answer's args and NDR body, built in place (the wire *_to()
  // encoders, as last_response_): reused, a record read or write allocates
  // nothing once they have grown to the longest answer.
  std::vector<std::uint8_t> rpc_args_, rpc_body_;
  Uuid last_activity_;
  std::uint32_t last_seq_ = 0;
  bool started_ = false;
  std::chrono::nanoseconds last_step_{0};
  std::chrono::nanoseconds now_{0};  // of the last poll (raise_alarm has no clock)
  std::chrono::nanoseconds next_idle_step_{0};
};

}  // namespace plc::profinet
