// The PROFIsafe V2 F-host protocol for one F-module, without any I/O: it
// takes the received F-input PDU and the application's output data and
// produces the next F-output PDU and the data the application may see.
//
// FOR TEST BENCHES AND SIMULATION ONLY, NOT CERTIFIED SAFETY SOFTWARE.
// The state machine follows spec nord-profisafe.md §8.2, which is itself
// [SPEC]-based (the NORD manual does not describe the host); TO BE VERIFIED
// AGAINST IEC 61784-3-3: the host state machine, when R_cons_nr is sent,
// whether OA_Req is a pulse or held, and start-up reintegration.
//
// Per cycle (called once per scan):
//   1. a response is new when Toggle_d == Toggle_h of the outstanding request;
//   2. a new response must carry the right CRC2 for the outstanding virtual
//      consecutive number (seeded with CRC1), otherwise: host CRC error;
//   3. a valid new response restarts the host watchdog; with no valid new
//      response for longer than F_WD_Time: host watchdog error, and the
//      outstanding request is abandoned (new toggle, R_cons_nr);
//   4. after any new response the next request is built: CN+1 (wrap to 1),
//      toggle flipped; after a communication fault, a request with
//      R_cons_nr = 1 and CN = 0 resynchronises host and device first.
// Passivation: the application sees 0 for every F-input and the device gets
// 0 with activate_FV. Reintegration: once the device reports the cause gone,
// ACK_REQ is raised; a rising edge of ACK_REI while ACK_REQ is set makes the
// host send OA_Req until the device clears FV_activated. Choices:
//   * first start-up reintegrates without ACK_REI (spec §8.2 step 4; the
//     anchors' TR-Electronic note says ACK after start-up: to verify);
//   * ACK_NEC = 0 lets device faults reintegrate automatically; communication
//     faults always need ACK_REI (Siemens F-I/O DB convention, §4.4);
//   * PASS_ON passivates without PASS_OUT and reintegrates when it drops.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "plc/fb/safety/safety_pdu.hpp"
#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc::safety {

enum class FHostState : std::uint8_t {
  Param = 0,          // F-parameters not yet accepted
  Startup = 1,        // parameters accepted, first exchange not yet valid
  Run = 2,            // valid process data
  PassiveComm = 3,    // CRC, cons-nr or watchdog fault (host or device side)
  PassiveDevice = 4,  // Device_Fault / unexpected FV_activated
  WaitAck = 5,        // cause gone, ACK_REQ raised, waiting for ACK_REI
  Reintegrating = 6,  // OA_Req sent, waiting for FV_activated = 0
};

struct FHostCommand {
  bool pass_on = false;
  bool ack_nec = true;
  bool ack_rei = false;
  bool ipar_en = false;
};

class FHostProtocol {
 public:
  void configure(std::uint16_t crc1, std::size_t out_len, std::size_t in_len, TIME wd_time);
  // F-parameters accepted by the device: start cyclic exchange at `now`.
  // First start reintegrates by itself; a restart after a lost device
  // (`after_fault`) keeps DIAG and needs ACK_REI like any communication fault.
  void start(TIME now, bool after_fault = false);
  // F-parameter record refused: stay in Param, remember the fault class.
  void param_failed(std::uint8_t diag_bit) { diag_ |= diag_bit; }
  // Back to Param (e.g. to send the F-parameters again).
  void reset();

  // One scan. `response` and `request` are full PDUs; `app_out` and `app_in`
  // are the application's F-data (out_len / in_len bytes).
  void cycle(TIME now, std::span<const std::uint8_t> response, std::span<std::uint8_t> request,
             std::span<const std::uint8_t> app_out, std::span<std::uint8_t> app_in,
             const FHostCommand& cmd);

  [[nodiscard]] FHostState state() const { return state_; }
  [[nodiscard]] bool pass_out() const { return state_ != FHostState::Run; }
  [[nodiscard]] bool qbad() const { return !data_valid_; }
  [[nodiscard]] bool ack_req() const { return state_ == FHostState::WaitAck; }
  [[nodiscard]] bool ipar_ok() const { return ipar_ok_; }
  [[nodiscard]] std::uint8_t diag() const { return diag_; }
  // True while app_in holds process data from a valid telegram.
  [[nodiscard]] bool data_valid() const { return data_valid_; }
  // Consecutive number of the telegram whose data is in app_in.
  [[nodiscard]] std::uint32_t accepted_cons_nr() const { return accepted_cn_; }
  // Consecutive number of the outstanding request.
  [[nodiscard]] std::uint32_t cons_nr() const { return cn_; }
  [[nodiscard]] bool device_fault_seen() const { return device_fault_seen_; }
  [[nodiscard]] std::uint64_t crc_errors() const { return crc_errors_; }
  [[nodiscard]] std::uint64_t watchdog_expiries() const { return wd_expiries_; }
  // Watchdog expiries since the last valid telegram (device lost for good).
  [[nodiscard]] std::uint32_t watchdog_expiries_in_row() const { return wd_in_row_; }

  // The protocol state, for the debugger and recording snapshots. All of it
  // is internal: the lengths index the PDUs, the rest is the state machine.
  PLC_REFLECT(crc1_, out_len_, in_len_, wd_, state_, cn_, accepted_cn_, toggle_h_, sent_any_,
              force_new_, resync_needed_, pending_rcons_, pending_fv_, comm_fault_seen_,
              device_fault_seen_, ipar_ok_, data_valid_, prev_ack_rei_, diag_, t_restart_,
              crc_errors_, wd_expiries_, wd_in_row_)
  PLC_INTERNAL(crc1_, out_len_, in_len_, wd_, state_, cn_, accepted_cn_, toggle_h_, sent_any_,
               force_new_, resync_needed_, pending_rcons_, pending_fv_, comm_fault_seen_,
               device_fault_seen_, ipar_ok_, data_valid_, prev_ack_rei_, diag_, t_restart_,
               crc_errors_, wd_expiries_, wd_in_row_)

 private:
  void comm_fault(std::uint8_t diag_bit);
  void device_fault(std::uint8_t diag_bit);
  void build_request(std::span<std::uint8_t> request, std::span<const std::uint8_t> app_out,
                     const FHostCommand& cmd);

  std::uint16_t crc1_ = 0;
  std::size_t out_len_ = 0, in_len_ = 0;
  TIME wd_{};
  FHostState state_ = FHostState::Param;
  std::uint32_t cn_ = 0;           // CN of the outstanding request
  std::uint32_t accepted_cn_ = 0;  // CN of the data in app_in
  bool toggle_h_ = false;
  bool sent_any_ = false;
  bool force_new_ = false;        // abandon the outstanding request (after host timeout)
  bool resync_needed_ = true;     // next request is an R_cons_nr request
  bool pending_rcons_ = false;    // the outstanding request is an R_cons_nr request
  bool pending_fv_ = false;       // the outstanding request carried activate_FV
  bool comm_fault_seen_ = false;  // since the last reintegration
  bool device_fault_seen_ = false;
  bool ipar_ok_ = false;
  bool data_valid_ = false;
  bool prev_ack_rei_ = false;
  std::uint8_t diag_ = 0;
  TIME t_restart_{};
  std::uint64_t crc_errors_ = 0, wd_expiries_ = 0;
  std::uint32_t wd_in_row_ = 0;
};

}  // namespace plc::safety
