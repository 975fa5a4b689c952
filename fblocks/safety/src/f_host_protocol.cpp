#include "plc/fb/safety/f_host_protocol.hpp"

#include <algorithm>

#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/f_host_diag.hpp"

namespace plc::safety {

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

}  // namespace plc::safety
