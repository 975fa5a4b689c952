// The checks a device makes on a Connect request before it accepts the AR,
// in the order and with the PNIO status codes of rt-labs p-net: first how
// src/device/pf_cmrpc.c reads the blocks (check_connect_blocks), then
// pf_cmdev_check_apdu in src/device/pf_cmdev.c (check_connect: AR block,
// IOCR blocks, expected submodules, the IOCRs' data and IOCS entries laid
// out and checked for bounds and overlap, block counts, AlarmCR block,
// ARRPC block; fieldbus-masters.md §1 item 2). Both ways: a controller that
// passes these passes a p-net device, and a Connect a p-net device accepts
// passes these. Where p-net accepts what IEC 61158-6-10 does not allow,
// we accept it too and connect_warnings() names the clause. The table of
// every check is in iec-io/profinet/README.md ("Connect checks").
//
// A refusal is ErrorCode 0xDB (Connect), ErrorDecode 0x81 (PNIO),
// ErrorCode1 = the faulty block (0x01 AR, 0x02 IOCR, 0x03 expected
// submodule, 0x04 AlarmCR, 0x07 ARRPC, 0x40 CMRPC), ErrorCode2 = the field
// (p-net's numbers). With several faults in one request we report the
// first in p-net's order; p-net sometimes reports a later one (its loops
// keep going and overwrite the status), the refusal is the same.
// Expected (sub)modules whose slot/subslot we have but whose ident differs
// are accepted and listed in the ModuleDiffBlock (module_diff()).
#pragma once

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "plc/profinet/description/device_description.hpp"
#include "plc/profinet/wire/blocks.hpp"

namespace plc::profinet {

namespace connect_error {
inline constexpr std::uint8_t kArBlock = 0x01;
inline constexpr std::uint8_t kIocrBlock = 0x02;
inline constexpr std::uint8_t kExpectedBlock = 0x03;
inline constexpr std::uint8_t kAlarmCrBlock = 0x04;
inline constexpr std::uint8_t kArRpcBlock = 0x07;
inline constexpr std::uint8_t kCmrpc = 0x40;
// ErrorCode2 of any block's header.
inline constexpr std::uint8_t kBlockLength = 0x01;
inline constexpr std::uint8_t kBlockVersionHigh = 0x02;
inline constexpr std::uint8_t kBlockVersionLow = 0x03;
// ErrorCode2 under kCmrpc.
inline constexpr std::uint8_t kCmrpcArgsLengthInvalid = 0x00;
inline constexpr std::uint8_t kCmrpcUnknownBlocks = 0x01;
inline constexpr std::uint8_t kCmrpcIocrMissing = 0x02;
inline constexpr std::uint8_t kCmrpcWrongBlockCount = 0x03;
inline constexpr std::uint8_t kCmrpcNoArResources = 0x04;
inline constexpr std::uint8_t kCmrpcArUuidUnknown = 0x05;
inline constexpr std::uint8_t kCmrpcStateConflict = 0x06;
}  // namespace connect_error

// IOCRProperties.RTClass (bits 0..3).
namespace rt_class {
inline constexpr std::uint32_t kClass1 = 1;
inline constexpr std::uint32_t kClass2 = 2;
inline constexpr std::uint32_t kClass3 = 3;
inline constexpr std::uint32_t kUdp = 4;
inline constexpr std::uint32_t kStream = 5;
}  // namespace rt_class
[[nodiscard]] constexpr std::uint32_t rt_class_of(const IocrBlockReq& c) {
  return c.iocr_properties & 0xFU;
}

// 0xDB 0x81 code1 code2.
[[nodiscard]] constexpr PnioStatus connect_refusal(std::uint8_t code1, std::uint8_t code2) {
  return {pnio_error::kCodeConnect, pnio_error::kDecodePnio, code1, code2};
}

// The blocks of the Connect args as p-net's pf_cmrpc.c reads them, before
// any value is checked: ARBlockReq first (AR 0x00), at most one input and
// one output IOCRBlockReq (p-net's default PNET_MAX_CR 2; a third: CMRPC
// 0x03), each known block exactly as long as its fields (block 0x01) and
// of version 1.0 (0x02 high, 0x03 low), no other block type and no block
// running past the args (CMRPC 0x01), no bytes after the last block
// (CMRPC 0x00). nullopt: decode_connect_request() can read them.
std::optional<PnioStatus> check_connect_blocks(std::span<const std::uint8_t> args);

// Every check of pf_cmdev_check_apdu, in p-net's order. nullopt: accepted.
std::optional<PnioStatus> check_connect(const ConnectRequest& req, const DeviceDescription& dev);

// What in a Connect that check_connect() accepts goes against IEC
// 61158-6-10 although p-net accepts it: one line each, naming the clause
// and what the device does about it. Empty for a Connect by the book.
std::vector<std::string> connect_warnings(const ConnectRequest& req);

// The FrameID of the output CR in the answer, as p-net chooses it: the
// controller's when it proposes one (a cyclic FrameID other than the input
// CR's), else (0xFFFF) the first FrameID of the RT class's range that the
// input CR does not use.
[[nodiscard]] std::uint16_t output_frame_id(const IocrBlockReq& output,
                                            std::uint16_t input_frame_id);

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
