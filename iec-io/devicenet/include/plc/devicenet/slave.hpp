// A DeviceNet slave (Group 2 Only server of the Predefined Master/Slave
// Connection Set) in front of a DeviceModel: the network side a simulated
// device needs, with no timing of its own. The host (dnslave, tests) calls
// tick() with its clock; the slave reads the bus, answers, and steps the
// model by the time that passed.
//
// It answers: the duplicate MAC ID check (and runs its own at start-up),
// Allocate/Release_Master/Slave_Connection_Set on the unconnected port (and
// on the explicit connection), Identity 0x01 (Get_Attribute_Single, Reset),
// DeviceNet 0x03, Assembly 0x04 attribute 3, Connection 0x05 instances 1
// (explicit) and 2 (poll) incl. the expected packet rate; every other
// explicit request goes to the model's query_record (explicit_message.hpp).
// Polled I/O reaches DeviceModel::step_io, which says whether a new poll
// command (or a Set of the output assembly's data) arrived since the last
// step; a message is handed to the model before the next explicit request
// that goes to it, so the model sees I/O messages and explicit services in
// the order they came. When the poll connection times out (4 x EPR without
// a poll) the model hears io_connection_lost().
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "plc/can/bus.hpp"
#include "plc/devicenet/explicit_frame.hpp"
#include "plc/io/device_model.hpp"
#include "plc/types.hpp"

namespace plc::devicenet {

struct SlaveIdentity {
  std::uint16_t vendor = 0;
  std::uint16_t device_type = 0;
  std::uint16_t product_code = 0;
  std::uint8_t major_rev = 1, minor_rev = 1;
  std::uint32_t serial = 0;
  std::string product_name;
};

struct SlaveConfig {
  std::uint8_t mac = 63;
  std::uint8_t baud_code = 2;  // DeviceNet object attr 2: 0 125k, 1 250k, 2 500k
  SlaveIdentity identity;
  std::uint8_t input_assembly = 100;   // produced (device -> master)
  std::uint8_t output_assembly = 150;  // consumed (master -> device)
  TIME dup_mac_wait = std::chrono::seconds(1);
};

// Fault switches (dnslave: per slave in the YAML and by signal).
struct SlaveFaults {
  bool silent = false;             // answer nothing at all (as if unplugged)
  int size_error = 0;              // produce this many bytes more (or fewer) than configured
  bool refuse_allocation = false;  // Allocate gets Error Response 0x02
};

struct SlaveCounters {
  std::uint64_t polls = 0, explicit_requests = 0, allocations = 0, io_timeouts = 0,
                explicit_timeouts = 0, bad_frames = 0, wrong_size_polls = 0;
};

class Slave {
 public:
  Slave(const SlaveConfig& cfg, std::unique_ptr<io::DeviceModel> model, can::Bus& bus);

  // Read every pending frame, answer, run the watchdogs, step the model by
  // now - previous tick.
  void tick(TIME now);

  SlaveFaults& faults() { return faults_; }
  [[nodiscard]] const SlaveCounters& counters() const { return counters_; }
  [[nodiscard]] bool online() const { return phase_ == Phase::Online; }
  [[nodiscard]] bool duplicate_found() const { return phase_ == Phase::DuplicateFound; }
  [[nodiscard]] std::uint8_t master() const { return master_; }
  [[nodiscard]] std::uint8_t allocation() const { return choice_; }
  [[nodiscard]] std::uint8_t poll_state() const { return poll_state_; }
  [[nodiscard]] std::uint8_t mac() const { return cfg_.mac; }
  io::DeviceModel& model() { return *model_; }
  [[nodiscard]] std::string describe() const;

 private:
  enum class Phase : std::uint8_t { DupMacCheck, Online, DuplicateFound };

  void on_frame(const can::Frame& f, TIME now);
  void on_dup_mac(const can::Frame& f);
  void on_explicit(const can::Frame& f, bool unconnected, TIME now);
  void on_poll(const can::Frame& f, TIME now);
  // Serves one message (service + body); writes the response into resp.
  std::size_t serve(std::span<const std::uint8_t> msg, bool unconnected,
                    std::span<std::uint8_t> resp, TIME now);
  std::size_t serve_allocate(std::span<const std::uint8_t> msg, std::span<std::uint8_t> resp,
                             TIME now);
  std::size_t serve_release(std::span<const std::uint8_t> msg, std::span<std::uint8_t> resp);
  std::size_t serve_object(std::uint8_t service, std::uint8_t cls, std::uint8_t inst,
                           std::span<const std::uint8_t> body, std::span<std::uint8_t> resp,
                           TIME now);
  void send_response(std::span<const std::uint8_t> msg);
  void release(std::uint8_t choice);
  void watchdogs(TIME now);
  // Hands a consumed output message to the model at once (a zero-length
  // step), so that an explicit request after it in the same tick comes later.
  void deliver_outputs(TIME now);

  SlaveConfig cfg_;
  std::unique_ptr<io::DeviceModel> model_;
  can::Bus& bus_;
  SlaveFaults faults_;
  SlaveCounters counters_;

  Phase phase_ = Phase::DupMacCheck;
  int dup_sent_ = 0;
  TIME dup_next_{0};
  bool started_ = false;
  TIME last_tick_{0};

  std::uint8_t master_ = 0xFF;
  std::uint8_t choice_ = 0;
  std::uint16_t explicit_epr_ms_ = 2500;
  TIME explicit_last_{0};
  std::uint8_t poll_state_ = 0;
  std::uint16_t poll_epr_ms_ = 0;
  TIME poll_last_{0};

  ExplicitReassembler rx_;
  ExplicitFrames tx_;
  std::size_t tx_next_ = 0;  // next fragment of tx_ to send after an ack
  IoReassembler poll_rx_;
  std::vector<std::uint8_t> inputs_, outputs_;
  bool outputs_new_ = false;  // outputs_ holds a message the model has not stepped with
  bool reset_pending_ = false;
};

}  // namespace plc::devicenet
