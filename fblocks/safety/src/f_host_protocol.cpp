#include "plc/fb/safety/f_host_protocol.hpp"

#include <algorithm>
#include <cstring>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/f_host_diag.hpp"

namespace plc::safety {

namespace {
// n (<= kMaxFData) bytes between distinct buffers; F-data of 4..8 bytes
// (NORD: 4 each way) as two 4-byte moves instead of a loop per byte.
inline void copy_fdata(std::uint8_t* dst, const std::uint8_t* src, std::size_t n) {
  if (n >= 4 && n <= 8) {
    std::memcpy(dst, src, 4);
    std::memcpy(dst + n - 4, src + n - 4, 4);
    return;
  }
  for (std::size_t i = 0; i < n; ++i) dst[i] = src[i];
}
}  // namespace

void FHostProtocol::configure(std::uint16_t crc1, std::size_t out_len, std::size_t in_len,
                              TIME wd_time) {
  crc1_ = crc1;
  out_len_ = std::min(out_len, kMaxFData);
  in_len_ = std::min(in_len, kMaxFData);
  wd_ = wd_time;
  reset();
}

void FHostProtocol::reset() {
  state_ = FHostState::Param;
  cn_ = 0;
  accepted_cn_ = 0;
  toggle_h_ = false;  // the first request flips it to 1: a device that has
                      // sent nothing yet (all zero) never looks like an answer
  sent_any_ = false;
  wd_tripped_ = false;
  resync_needed_ = true;
  pending_rcons_ = false;
  pending_fv_ = true;
  comm_fault_seen_ = false;
  device_fault_seen_ = false;
  ipar_ok_ = false;
  data_valid_ = false;
}

void FHostProtocol::start(TIME now, bool after_fault) {
  reset();
  state_ = FHostState::Startup;
  if (!after_fault) diag_ = 0;
  comm_fault_seen_ = after_fault;
  wd_in_row_ = 0;
  t_sent_ = now;
}

void FHostProtocol::comm_fault(std::uint8_t diag_bit) {
  diag_ |= diag_bit;
  comm_fault_seen_ = true;
  resync_needed_ = true;
  state_ = FHostState::PassiveComm;
}

void FHostProtocol::device_fault(std::uint8_t diag_bit) {
  diag_ |= diag_bit;
  device_fault_seen_ = diag_bit != 0 || device_fault_seen_;
  if (state_ != FHostState::PassiveComm) state_ = FHostState::PassiveDevice;
}

void FHostProtocol::cycle(TIME now, std::span<const std::uint8_t> response,
                          std::span<std::uint8_t> request, std::span<const std::uint8_t> app_out,
                          std::span<std::uint8_t> app_in, const FHostCommand& cmd) {
  // ACK_REQ as the program saw it after the last scan: an acknowledgement
  // only counts for a request the operator could see.
  const bool ack_req_shown = state_ == FHostState::WaitAck;
  const bool ack_edge = cmd.ack_rei && !prev_ack_rei_;
  prev_ack_rei_ = cmd.ack_rei;

  if (state_ == FHostState::Param) {
    std::fill(request.begin(), request.end(), std::uint8_t{0});
    std::fill(app_in.begin(), app_in.end(), std::uint8_t{0});
    data_valid_ = false;
    return;
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
    copy_fdata(app_in.data(), response.data(), in_len_);
    accepted_cn_ = cn_;
    data_valid_ = true;
    ++deliveries_;
  } else if (!(may_pass && data_valid_ && !answered)) {
    std::fill(app_in.begin(), app_in.begin() + static_cast<std::ptrdiff_t>(in_len_),
              std::uint8_t{0});
    data_valid_ = false;
  }

  if (answered || !sent_any_) build_request(now, request, app_out, cmd);
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
    copy_fdata(request.data(), app_out.data(), out_len_);
  } else {
    std::fill_n(request.begin(), out_len_, std::uint8_t{0});
  }
  request_crc_.seal_pdu(request, out_len_, control, cn_, crc1_);
}

}  // namespace plc::safety
