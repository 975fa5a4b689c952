#include "plc/profinet/device/output_acceptance.hpp"

#include <cstring>

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

namespace {
// Two loads, not a memcmp call (once per output frame).
bool same_mac(const Mac& a, const Mac& b) {
  std::uint32_t a4 = 0, b4 = 0;
  std::uint16_t a2 = 0, b2 = 0;
  std::memcpy(&a4, a.data(), 4);
  std::memcpy(&a2, a.data() + 4, 2);
  std::memcpy(&b4, b.data(), 4);
  std::memcpy(&b2, b.data() + 4, 2);
  return a4 == b4 && a2 == b2;
}
}  // namespace

std::optional<OutputReject> OutputAcceptance::check(const OutputFrameFacts& f) {
  std::optional<OutputReject> r;
  if (!same_mac(f.source, controller_))
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
