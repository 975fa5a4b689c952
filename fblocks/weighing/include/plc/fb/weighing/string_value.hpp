// PR5510_ReadString / PR5510_WriteString: a 20-character STRING through
// five consecutive codes of 4 characters each (spec §4.3: "always 20
// characters, transferred as 5 x 4"; the code sequence, padding and
// character order are [INFERRED], see window_codec.hpp). Execute-style.
#pragma once

#include <array>

#include "plc/fb/weighing/pr5510_device.hpp"

namespace plc::weighing {

class PR5510_ReadString {
 public:
  PR5510_Device* Device = nullptr;
  BOOL Execute{};
  USINT BaseCode{};  // first of five application read codes

  BOOL Done{};
  BOOL Busy{};
  BOOL Error{};
  WORD ErrorID{};
  STRING Text{};  // trailing padding removed

  PLC_REFLECT(Execute, BaseCode, Done, Busy, Error, ErrorID, Text,
              /* internal state */ slot_, prev_execute_, chunk_, buf_)
  PLC_INTERNAL(slot_, prev_execute_, chunk_, buf_)

  void operator()(const ScanContext& ctx);

 private:
  int slot_ = PR5510_Device::kNoSlot;
  bool prev_execute_ = false;
  std::uint8_t chunk_ = 0;
  std::array<SINT, kStringLength> buf_{};  // chunks read so far (SINT: reflectable)
};

class PR5510_WriteString {
 public:
  PR5510_Device* Device = nullptr;
  BOOL Execute{};
  USINT BaseCode{};  // first of five application write codes
  STRING Text{};     // first 20 characters are sent, padded with spaces

  BOOL Done{};
  BOOL Busy{};
  BOOL Error{};
  WORD ErrorID{};

  PLC_REFLECT(Execute, BaseCode, Text, Done, Busy, Error, ErrorID,
              /* internal state */ slot_, prev_execute_, chunk_, latched_)
  PLC_INTERNAL(slot_, prev_execute_, chunk_, latched_)

  void operator()(const ScanContext& ctx);

 private:
  int slot_ = PR5510_Device::kNoSlot;
  bool prev_execute_ = false;
  std::uint8_t chunk_ = 0;
  STRING latched_{};
};

}  // namespace plc::weighing
