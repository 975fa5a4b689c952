// The checks a device makes on a Connect request before it accepts the AR,
// in the order and with the PNIO status codes of rt-labs p-net's
// src/device/pf_cmdev.c (pf_cmdev_check_apdu: AR block, IOCR blocks,
// expected submodules, IOCR/API cross-checks, block counts, AlarmCR block;
// fieldbus-masters.md §1 item 2). A controller that passes these also
// passes a p-net device.
//
// A refusal is ErrorCode 0xDB (Connect), ErrorDecode 0x81 (PNIO),
// ErrorCode1 = the faulty block (0x01 AR, 0x02 IOCR, 0x03 expected
// submodule, 0x04 AlarmCR, 0x40 CMRPC), ErrorCode2 = the field (p-net's
// numbers). Expected (sub)modules whose slot/subslot we have but whose ident
// differs are accepted and listed in the ModuleDiffBlock (module_diff()).
#pragma once

#include <chrono>
#include <optional>

#include "plc/profinet/description/device_description.hpp"
#include "plc/profinet/wire/blocks.hpp"

namespace plc::profinet {

namespace connect_error {
inline constexpr std::uint8_t kArBlock = 0x01;
inline constexpr std::uint8_t kIocrBlock = 0x02;
inline constexpr std::uint8_t kExpectedBlock = 0x03;
inline constexpr std::uint8_t kAlarmCrBlock = 0x04;
inline constexpr std::uint8_t kCmrpc = 0x40;
// ErrorCode2 under kCmrpc.
inline constexpr std::uint8_t kCmrpcArgsLengthInvalid = 0x00;
inline constexpr std::uint8_t kCmrpcUnknownBlocks = 0x01;
inline constexpr std::uint8_t kCmrpcIocrMissing = 0x02;
inline constexpr std::uint8_t kCmrpcWrongBlockCount = 0x03;
inline constexpr std::uint8_t kCmrpcNoArResources = 0x04;
inline constexpr std::uint8_t kCmrpcArUuidUnknown = 0x05;
inline constexpr std::uint8_t kCmrpcStateConflict = 0x06;
}  // namespace connect_error

// 0xDB 0x81 code1 code2.
[[nodiscard]] constexpr PnioStatus connect_refusal(std::uint8_t code1, std::uint8_t code2) {
  return {pnio_error::kCodeConnect, pnio_error::kDecodePnio, code1, code2};
}

// Every check of pf_cmdev_check_apdu, in p-net's order. nullopt: accepted.
std::optional<PnioStatus> check_connect(const ConnectRequest& req, const DeviceDescription& dev);

// The ModuleDiffBlock for an accepted request: every expected module whose
// ident differs (WrongModule) and every expected submodule whose ident
// differs (Wrong); nullopt when everything matches.
std::optional<ModuleDiffBlock> module_diff(const ConnectRequest& req, const DeviceDescription& dev);

// SendClockFactor x ReductionRatio x 31.25 us.
[[nodiscard]] constexpr std::chrono::nanoseconds send_interval(std::uint16_t send_clock_factor,
                                                               std::uint16_t reduction_ratio) {
  return std::chrono::nanoseconds(std::int64_t{send_clock_factor} * reduction_ratio * 31250);
}

}  // namespace plc::profinet
