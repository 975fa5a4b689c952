#include "plc/profinet/device/output_acceptance.hpp"

namespace plc::profinet {

const char* to_string(OutputReject r) {
  switch (r) {
    case OutputReject::WrongSource:
      return "wrong source MAC";
    case OutputReject::WrongLength:
      return "wrong length";
    case OutputReject::TransferStatus:
      return "TransferStatus not 0";
    case OutputReject::CounterNotAdvanced:
      return "cycle counter not advanced";
    case OutputReject::DataInvalid:
      return "DataValid not set";
  }
  return "?";
}

void OutputAcceptance::start(const Mac& controller, std::size_t frame_length) {
  controller_ = controller;
  length_ = frame_length;
  have_counter_ = false;
}

std::optional<OutputReject> OutputAcceptance::check(const OutputFrameFacts& f) {
  std::optional<OutputReject> r;
  if (f.source != controller_)
    r = OutputReject::WrongSource;
  else if (f.length_without_vlan != length_)
    r = OutputReject::WrongLength;
  else if (f.transfer_status != 0)
    r = OutputReject::TransferStatus;
  else if (have_counter_ && !cycle_counter_advanced(last_counter_, f.cycle_counter))
    r = OutputReject::CounterNotAdvanced;
  else if ((f.data_status & 0x04) == 0)
    r = OutputReject::DataInvalid;
  if (r) {
    ++rejected_[static_cast<std::size_t>(*r)];
    return r;
  }
  have_counter_ = true;
  last_counter_ = f.cycle_counter;
  ++accepted_;
  return std::nullopt;
}

}  // namespace plc::profinet
