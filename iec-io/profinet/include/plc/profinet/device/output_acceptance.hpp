// Which of the controller's RT_CLASS_1 frames the device takes, and why it
// drops the others: the consumer checks of rt-labs p-net's CPM
// (src/device/pf_cpm.c, fieldbus-masters.md §1 item 6), so that what passes
// our device also passes a p-net device.
//
// A frame is taken when, in this order:
//  * its source MAC is the controller's (CMInitiatorMacAdd of the Connect);
//  * its length without VLAN tag is exactly the length the output IOCR
//    defines (14-byte header + FrameID + C_SDU + 4-byte APDU status);
//  * TransferStatus is 0;
//  * the cycle counter advanced by 1..61440 (mod 2^16) since the last frame
//    taken (p-net pf_cpm_check_cycle: a repeated or slightly older counter is
//    a duplicate); the first frame after Connect is taken with any counter;
//  * DataStatus has DataValid (bit 2).
// Each dropped frame counts once, under the first check it fails.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>

#include "plc/profinet/link/address.hpp"
#include "plc/profinet/wire/cyclic.hpp"  // cycle_counter_advanced

namespace plc::profinet {

enum class OutputReject : std::uint8_t {
  WrongSource,         // source MAC is not the controller's
  WrongLength,         // length differs from the output IOCR's
  TransferStatus,      // TransferStatus != 0
  CounterNotAdvanced,  // cycle counter repeated / went back
  DataInvalid,         // DataStatus.DataValid = 0
};
inline constexpr std::size_t kOutputRejectKinds = 5;
[[nodiscard]] const char* to_string(OutputReject r);

// The fields of a received frame the checks look at.
struct OutputFrameFacts {
  Mac source{};
  std::size_t length_without_vlan = 0;
  std::uint16_t cycle_counter = 0;
  std::uint8_t data_status = 0;
  std::uint8_t transfer_status = 0;
};

class OutputAcceptance {
 public:
  // A new AR: the controller's MAC and the exact frame length (no VLAN tag).
  void start(const Mac& controller, std::size_t frame_length);
  // nullopt: take the frame (the counter is remembered); else why it is
  // dropped. Inline: once per output frame.
  std::optional<OutputReject> check(const OutputFrameFacts& f) {
    std::optional<OutputReject> r;
    if (!same_mac(f.source.data(), controller_.data()))
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

  [[nodiscard]] std::uint64_t rejected(OutputReject r) const {
    return rejected_[static_cast<std::size_t>(r)];
  }
  [[nodiscard]] std::uint64_t accepted() const { return accepted_; }

 private:
  Mac controller_{};
  std::size_t length_ = 0;
  bool have_counter_ = false;
  std::uint16_t last_counter_ = 0;
  std::array<std::uint64_t, kOutputRejectKinds> rejected_{};
  std::uint64_t accepted_ = 0;
};

}  // namespace plc::profinet
