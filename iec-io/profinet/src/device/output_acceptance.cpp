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

}  // namespace plc::profinet
