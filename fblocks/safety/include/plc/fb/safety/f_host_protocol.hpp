// The PROFIsafe V2 F-host protocol for one F-module, without any I/O: it
// takes the received F-input PDU and the application's output data and
// produces the next F-output PDU and the data the application may see.
//
// FOR TEST BENCHES AND SIMULATION ONLY, NOT CERTIFIED SAFETY SOFTWARE.
// The state machine follows spec nord-profisafe.md §8.2, which is itself
// [SPEC]-based (the NORD manual does not describe the host); TO BE VERIFIED
// AGAINST IEC 61784-3-3: the host state machine, when R_cons_nr is sent,
// whether OA_Req is a pulse or held, and start-up reintegration. The
// consecutive-number semantics (0 with R_cons_nr after a reset, answered
// with cons_nr_R; +1 per telegram; Toggle_h alternating) match real traffic
// (tests/safety/test_wire_vectors.cpp).
//
// Per cycle (called once per scan):
//   1. the answer to the outstanding request is the telegram whose Toggle_d
//      equals that request's Toggle_h;
//   2. it counts only if it arrives within F_WD_Time of when that request
//      was sent, and carries the right CRC2 for the request's virtual
//      consecutive number (seeded with CRC1); otherwise: host watchdog or
//      host CRC error;
//   3. with no answer for longer than F_WD_Time: host watchdog error;
//   4. after each answer (valid, corrupt or late) the next request is built:
//      CN+1 (wrap to 1), toggle flipped; after a communication fault it is
//      an R_cons_nr request with CN = 0 that resynchronises host and device.
//
// No data older than F_WD_Time reaches the application (the watchdog
// promise), under any delay the channel adds, also across restarts:
//   * the host never has more than one request outstanding, and never gives
//     one up: when the watchdog trips, the host passivates but keeps waiting
//     for the answer to the request it sent; only that answer, however late,
//     lets it send the next (R_cons_nr) request. Giving a request up and
//     sending a new one is what let a late answer from before a restart
//     match the restarted sequence (same number, same toggle, valid CRC2):
//     after each reset the numbers start again at 0 and the toggle has only
//     two values, so no content tells the two exchanges apart;
//   * so, with the channel delivering the device's telegrams in the order
//     the device sent them (a fieldbus delays or skips cyclic frames, it does
//     not reorder them), the first telegram with the outstanding toggle that
//     follows the previous answer was produced by the device after it
//     received the outstanding request: every answer provably belongs to the
//     current request, hence to the current start-up;
//   * a timestamp per sent request bounds the age: the device produces its
//     answer after the request was sent, and an answer is taken only within
//     F_WD_Time of sending; a late answer is never used, only drained;
//   * telegrams out of order (repetition, masquerade, corruption) fail the
//     CRC2 check, and ACK_REI only counts while ACK_REQ was already shown, so
//     the OA_Req exchange after a fault is never one of the first two of a
//     start-up (numbers 0 and 1, the only ones a repeated telegram from the
//     end of the previous start-up could match);
//   * the F_MODULE gives a request up in one case, when the device stays
//     silent for three watchdog periods and is parameterised again; at most
//     one telegram from before can then still be in flight, it can only be
//     taken for the R_cons_nr answer (which carries no data), and that
//     restart needs ACK_REI like every communication fault.
// Held data: between answers the last valid data stays until the next
// answer or the watchdog; data accepted at age <= F_WD_Time can so be shown
// until it is up to 2 x F_WD_Time old, as in PROFIsafe.
//
// Passivation: the application sees 0 for every F-input and the device gets
// 0 with activate_FV. Reintegration: once the R_cons_nr exchange has been
// answered validly and in time and the device reports the cause gone,
// ACK_REQ is raised; a rising edge of ACK_REI while ACK_REQ is set makes the
// host send OA_Req until the device clears FV_activated. Choices:
//   * first start-up reintegrates without ACK_REI (spec §8.2 step 4; the
//     anchors' TR-Electronic note says ACK after start-up: to verify);
//   * ACK_NEC = 0 lets device faults reintegrate automatically; communication
//     faults always need ACK_REI (Siemens F-I/O DB convention, §4.4);
//   * PASS_ON passivates without PASS_OUT and reintegrates when it drops.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/crc2_cache.hpp"
#include "plc/fb/safety/f_host_diag.hpp"
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
  // are the application's F-data (out_len / in_len bytes). SteadyPath false
  // (tests only) takes the general path for the steady exchange too. An
  // F-module whose F-data lengths are constants gives them as InLen/OutLen
  // (0: not known): the steady path then indexes and copies with them, once
  // it has checked that they are the configured ones. Returns true when the
  // scan was the steady exchange (state Run before and after, the answer
  // valid, in time and delivered, PASS_ON off), so a caller may show its
  // outputs for that without reading the state back; false otherwise.
  template <bool SteadyPath = true, std::size_t InLen = 0, std::size_t OutLen = 0>
  bool cycle(TIME now, std::span<const std::uint8_t> response, std::span<std::uint8_t> request,
             std::span<const std::uint8_t> app_out, std::span<std::uint8_t> app_in,
             const FHostCommand& cmd);
  // cycle()'s steady exchange alone: true when the scan was that exchange
  // (and done); false when it was not, and then nothing has changed, so
  // cycle() gives the scan. An F-module calls it first, inline, and cycle()
  // out of line when it returns false.
  template <std::size_t InLen = 0, std::size_t OutLen = 0>
  bool steady_exchange(TIME now, std::span<const std::uint8_t> response,
                       std::span<std::uint8_t> request, std::span<const std::uint8_t> app_out,
                       std::span<std::uint8_t> app_in, const FHostCommand& cmd);

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
  // Answers that came after F_WD_Time (drained, never used).
  [[nodiscard]] std::uint64_t late_answers() const { return late_answers_; }
  // Times valid process data was handed to the application.
  [[nodiscard]] std::uint64_t deliveries() const { return deliveries_; }
  // Watchdog expiries since the last valid telegram (device lost for good).
  [[nodiscard]] std::uint32_t watchdog_expiries_in_row() const { return wd_in_row_; }

  // The protocol state, for the debugger and recording snapshots. All of it
  // is internal: the lengths index the PDUs, the rest is the state machine.
  PLC_REFLECT(crc1_, out_len_, in_len_, wd_, state_, cn_, accepted_cn_, toggle_h_, sent_any_,
              wd_tripped_, resync_needed_, pending_rcons_, pending_fv_, comm_fault_seen_,
              device_fault_seen_, ipar_ok_, data_valid_, prev_ack_rei_, diag_, t_sent_,
              wd_period_from_, crc_errors_, wd_expiries_, late_answers_, deliveries_, wd_in_row_)
  PLC_INTERNAL(crc1_, out_len_, in_len_, wd_, state_, cn_, accepted_cn_, toggle_h_, sent_any_,
               wd_tripped_, resync_needed_, pending_rcons_, pending_fv_, comm_fault_seen_,
               device_fault_seen_, ipar_ok_, data_valid_, prev_ack_rei_, diag_, t_sent_,
               wd_period_from_, crc_errors_, wd_expiries_, late_answers_, deliveries_, wd_in_row_)

 private:
  void comm_fault(std::uint8_t diag_bit);
  void device_fault(std::uint8_t diag_bit);
  void build_request(TIME now, std::span<std::uint8_t> request,
                     std::span<const std::uint8_t> app_out, const FHostCommand& cmd);

  std::uint16_t crc1_ = 0;
  std::size_t out_len_ = 0, in_len_ = 0;
  TIME wd_{};
  FHostState state_ = FHostState::Param;
  std::uint32_t cn_ = 0;           // CN of the outstanding request
  std::uint32_t accepted_cn_ = 0;  // CN of the data in app_in
  bool toggle_h_ = false;
  bool sent_any_ = false;
  bool wd_tripped_ = false;       // the watchdog tripped for the outstanding request
  bool resync_needed_ = true;     // next request is an R_cons_nr request
  bool pending_rcons_ = false;    // the outstanding request is an R_cons_nr request
  bool pending_fv_ = false;       // the outstanding request carried activate_FV
  bool comm_fault_seen_ = false;  // since the last reintegration
  bool device_fault_seen_ = false;
  bool ipar_ok_ = false;
  bool data_valid_ = false;
  bool prev_ack_rei_ = false;
  std::uint8_t diag_ = 0;
  TIME t_sent_{};          // when the outstanding request was sent
  TIME wd_period_from_{};  // start of the current watchdog period after a trip
  std::uint64_t crc_errors_ = 0, wd_expiries_ = 0, late_answers_ = 0, deliveries_ = 0;
  std::uint32_t wd_in_row_ = 0;
  // CRC2 of the requests built and the responses checked. Not reflected:
  // a cache whose results are compute_crc2()'s whatever it holds, so a
  // snapshot restored without it gives the same telegrams.
  Crc2Cache request_crc_, response_crc_;
};

namespace detail {
// n (<= kMaxFData) bytes between distinct buffers; F-data of 4..8 bytes
// (NORD: 4 each way) as two 4-byte moves instead of a loop per byte.
inline void copy_fdata(std::uint8_t* dst, const std::uint8_t* src, std::size_t n) {
  if (n >= 4 && n <= 8) {
    // Both words loaded before either store: the buffers are distinct, and
    // with n == 4 (a constant where cycle() is inlined) the two moves are
    // then one (the first store could alias the second load for the
    // compiler, which loaded and stored the same word twice).
    std::uint32_t head, tail;
    std::memcpy(&head, src, 4);
    std::memcpy(&tail, src + n - 4, 4);
    std::memcpy(dst, &head, 4);
    std::memcpy(dst + n - 4, &tail, 4);
    return;
  }
  for (std::size_t i = 0; i < n; ++i) dst[i] = src[i];
}
}  // namespace detail

// cycle() and build_request() are inline: an F-module calls cycle() every
// scan, and as a call (five spans by value) it cost the marshalling of its
// arguments and its register saves every scan.
template <bool SteadyPath, std::size_t InLen, std::size_t OutLen>
inline bool FHostProtocol::cycle(TIME now, std::span<const std::uint8_t> response,
                                 std::span<std::uint8_t> request,
                                 std::span<const std::uint8_t> app_out,
                                 std::span<std::uint8_t> app_in, const FHostCommand& cmd) {
  // The steady exchange, nearly every scan in Run: the outstanding request
  // answered in time with a valid CRC2, no fault or FV_activated in the
  // status byte, no fail-safe values asked. What the general path below
  // does then, without its other branches: the data to the application and
  // the next request (build_request() with state Run and PASS_ON off:
  // CN + 1, or 0 with R_cons_nr; no OA_Req, no activate_FV; the F-output
  // data). In Run no acknowledgement counts (ACK_REQ was not shown), so of
  // the general path's ACK_REI handling only the edge memory remains. Asked
  // first, before the general path's preamble, so that the steady scan
  // reads only what it needs (with a constant length, the status byte at
  // a constant place). SteadyPathEqualsTheGeneralPath
  // (test_host_protocol.cpp) compares the two over a random walk of
  // faults, silences and commands.
  if constexpr (SteadyPath) {
    if (steady_exchange<InLen, OutLen>(now, response, request, app_out, app_in, cmd)) return true;
  }

  // ACK_REQ as the program saw it after the last scan: an acknowledgement
  // only counts for a request the operator could see.
  const bool ack_req_shown = state_ == FHostState::WaitAck;
  const bool ack_edge = cmd.ack_rei && !prev_ack_rei_;
  prev_ack_rei_ = cmd.ack_rei;

  if (state_ == FHostState::Param) {
    std::fill(request.begin(), request.end(), std::uint8_t{0});
    std::fill(app_in.begin(), app_in.end(), std::uint8_t{0});
    data_valid_ = false;
    return false;
  }

  const std::uint8_t status = response[in_len_];
  // The answer to the outstanding request (see the header: one request at
  // a time, so in an in-order channel the first telegram with its toggle
  // answers it and nothing older can follow).
  const bool answered = sent_any_ && (((status & sb::kToggleD) != 0) == toggle_h_);
  // Its data is no older than the request: in time means no older than
  // F_WD_Time, measured from when this request was sent.
  const bool in_time = now - t_sent_ <= wd_;
  bool valid = false;
  if (answered) {
    wd_in_row_ = 0;  // the device is there, however late
    if (!in_time) {
      // Late: its data may be older than F_WD_Time. Never used; it only
      // drains the channel, and the exchange restarts with R_cons_nr.
      ++late_answers_;
      if (!wd_tripped_) {
        ++wd_expiries_;
        comm_fault(diag::kHostWd);
      }
    } else if (!response_crc_.check_pdu(response, in_len_, cn_, crc1_)) {
      ++crc_errors_;
      comm_fault(diag::kHostCrc);
    } else {
      valid = true;
      ipar_ok_ = (status & sb::kIparOk) != 0;
      // The reset exchange is done once a valid answer to R_cons_nr arrives;
      // an answer that reports a communication error means the device did
      // not take the reset, and comm_fault() asks for it again.
      if (pending_rcons_) resync_needed_ = false;
      if (status & sb::kCeCrc) comm_fault(diag::kDevCeCrc);
      if (status & sb::kWdTimeout) comm_fault(diag::kDevWd);
      if (status & sb::kDeviceFault) device_fault(diag::kDevFault);
    }
  } else if (!in_time && !wd_tripped_) {
    // Host watchdog: passivate, but keep the request outstanding (see the
    // header for why it is not abandoned).
    ++wd_expiries_;
    ++wd_in_row_;
    comm_fault(diag::kHostWd);
    wd_tripped_ = true;
    wd_period_from_ = now;
  } else if (wd_tripped_ && now - wd_period_from_ > wd_) {
    ++wd_in_row_;  // still no answer: one more watchdog period (device lost?)
    wd_period_from_ = now;
  }

  const bool dev_clean = (status & (sb::kCeCrc | sb::kWdTimeout | sb::kDeviceFault)) == 0;
  const bool fv = (status & sb::kFvActivated) != 0;

  if (valid) {
    switch (state_) {
      case FHostState::Run:
        // FV_activated that the host did not ask for: the device passivated
        // itself; treat it as a device-side passivation.
        if (fv && !pending_fv_) device_fault(0);
        break;
      case FHostState::Startup:
        if (!resync_needed_ && dev_clean)
          state_ = comm_fault_seen_ ? FHostState::WaitAck : FHostState::Reintegrating;
        break;
      case FHostState::PassiveComm:
      case FHostState::PassiveDevice:
        if (!resync_needed_ && dev_clean) {
          const bool need_ack = comm_fault_seen_ || cmd.ack_nec;
          state_ = need_ack ? FHostState::WaitAck : FHostState::Reintegrating;
        }
        break;
      case FHostState::Reintegrating:
        if (dev_clean && !fv && !resync_needed_) {
          state_ = FHostState::Run;
          diag_ = 0;
          comm_fault_seen_ = false;
          device_fault_seen_ = false;
        }
        break;
      default:
        break;
    }
  }
  // ACK_REI is only taken while ACK_REQ is set (and was shown).
  if (ack_req_shown && state_ == FHostState::WaitAck && ack_edge)
    state_ = FHostState::Reintegrating;

  // Data for the application: only from this scan's valid telegram in Run
  // with no fail-safe values active; the last valid data stays while no new
  // telegram is due; everything else is the fail-safe value 0.
  const bool may_pass = state_ == FHostState::Run && !cmd.pass_on;
  if (valid && may_pass && !fv) {
    // app_in holds in_len_ bytes (the caller's contract); the bound tells
    // the compiler so when app_in is a member array of the caller.
    detail::copy_fdata(app_in.data(), response.data(), std::min(in_len_, app_in.size()));
    accepted_cn_ = cn_;
    data_valid_ = true;
    ++deliveries_;
  } else if (!(may_pass && data_valid_ && !answered)) {
    std::fill(app_in.begin(), app_in.begin() + static_cast<std::ptrdiff_t>(in_len_),
              std::uint8_t{0});
    data_valid_ = false;
  }

  if (answered || !sent_any_) build_request(now, request, app_out, cmd);
  return false;
}

// The steady exchange of cycle() (see there): true when it was taken. It
// changes nothing when it returns false (the CRC2 cache aside, whose
// results do not depend on what it holds), so the general path may follow.
template <std::size_t InLen, std::size_t OutLen>
[[gnu::always_inline]] inline bool FHostProtocol::steady_exchange(
    TIME now, std::span<const std::uint8_t> response, std::span<std::uint8_t> request,
    std::span<const std::uint8_t> app_out, std::span<std::uint8_t> app_in,
    const FHostCommand& cmd) {
  if (state_ == FHostState::Run && sent_any_ && !cmd.pass_on && (InLen == 0 || in_len_ == InLen) &&
      (OutLen == 0 || out_len_ == OutLen)) {
    const std::size_t in_len = InLen != 0 ? InLen : in_len_;
    const std::uint8_t status = response[in_len];
    if ((((status & sb::kToggleD) != 0) == toggle_h_) && now - t_sent_ <= wd_ &&
        (status & (sb::kCeCrc | sb::kWdTimeout | sb::kDeviceFault | sb::kFvActivated)) == 0 &&
        response_crc_.check_pdu(response, in_len, cn_, crc1_)) {
      prev_ack_rei_ = cmd.ack_rei;
      // Members read once into locals: the byte stores into the PDUs below
      // may alias them for the compiler, which would reload each.
      const std::uint32_t cn = cn_;
      const std::size_t out_len = OutLen != 0 ? OutLen : out_len_;
      const std::uint16_t crc1 = crc1_;
      const bool resync = resync_needed_ && !pending_rcons_;  // answered: a reset is done
      const bool toggle = !toggle_h_;
      const std::uint32_t next_cn = resync ? 0 : next_cons_nr(cn);
      wd_in_row_ = 0;
      ipar_ok_ = (status & sb::kIparOk) != 0;
      resync_needed_ = resync;
      accepted_cn_ = cn;
      data_valid_ = true;
      ++deliveries_;
      sent_any_ = true;
      t_sent_ = now;
      wd_tripped_ = false;
      pending_rcons_ = resync;
      cn_ = next_cn;
      toggle_h_ = toggle;
      pending_fv_ = false;
      std::uint8_t control = toggle ? cb::kToggleH : 0;
      if (cmd.ipar_en) control |= cb::kIparEn;
      if (resync) control |= cb::kRConsNr;
      detail::copy_fdata(app_in.data(), response.data(), in_len);
      detail::copy_fdata(request.data(), app_out.data(), out_len);
      request_crc_.seal_pdu(request, out_len, control, next_cn, crc1);
      return true;
    }
  }
  return false;
}

// Inline into cycle(), its one caller: a request is built every exchange.
[[gnu::always_inline]] inline void FHostProtocol::build_request(
    TIME now, std::span<std::uint8_t> request, std::span<const std::uint8_t> app_out,
    const FHostCommand& cmd) {
  sent_any_ = true;
  t_sent_ = now;
  wd_tripped_ = false;
  pending_rcons_ = resync_needed_;
  cn_ = resync_needed_ ? 0 : next_cons_nr(cn_);
  toggle_h_ = !toggle_h_;

  const bool run = state_ == FHostState::Run;
  const bool activate_fv = cmd.pass_on || !(run || state_ == FHostState::Reintegrating);
  pending_fv_ = activate_fv || !run;
  std::uint8_t control = toggle_h_ ? cb::kToggleH : 0;
  if (cmd.ipar_en) control |= cb::kIparEn;
  if (state_ == FHostState::Reintegrating) control |= cb::kOaReq;
  if (pending_rcons_) control |= cb::kRConsNr;
  if (activate_fv) control |= cb::kActivateFv;

  // The F-output data, or the fail-safe value 0, straight into the PDU.
  const bool pass = run && !cmd.pass_on;
  if (pass) {
    detail::copy_fdata(request.data(), app_out.data(), out_len_);
  } else {
    std::fill_n(request.begin(), out_len_, std::uint8_t{0});
  }
  request_crc_.seal_pdu(request, out_len_, control, cn_, crc1_);
}

}  // namespace plc::safety
