// check_connect_blocks() (connect_check.hpp): the Connect's blocks read as
// p-net's pf_cmrpc_rm_connect_interpret_ind reads them, before any field
// value is checked. Where p-net's reader reports a block whose fields do
// not fill its BlockLength in more than one way (it reads past a short
// block into the next one), we report it as that block's length (0x01).
#include "plc/profinet/device/connect_check.hpp"

namespace plc::profinet {

namespace {

using connect_error::kCmrpc;

// ErrorCode1 of a block type we read; 0: a block we do not take.
std::uint8_t block_code(std::uint16_t type) {
  switch (type) {
    case block::kArBlockReq:
      return connect_error::kArBlock;
    case block::kIocrBlockReq:
      return connect_error::kIocrBlock;
    case block::kExpectedSubmoduleBlockReq:
      return connect_error::kExpectedBlock;
    case block::kAlarmCrBlockReq:
      return connect_error::kAlarmCrBlock;
    case block::kArRpcBlockReq:
      return connect_error::kArRpcBlock;
    default:
      return 0;
  }
}

// Whether the block's fields fill exactly its BlockLength (its version is
// checked apart, after the length, as p-net does).
bool fields_fill_block(BlockView v) {
  v.version_high = 1;
  v.version_low = 0;
  switch (v.type) {
    case block::kArBlockReq: {
      ArBlockReq b;
      return decode_block(v, b).ok();
    }
    case block::kIocrBlockReq: {
      IocrBlockReq b;
      return decode_block(v, b).ok();
    }
    case block::kExpectedSubmoduleBlockReq: {
      ExpectedSubmoduleBlockReq b;
      return decode_block(v, b).ok();
    }
    case block::kAlarmCrBlockReq: {
      AlarmCrBlockReq b;
      return decode_block(v, b).ok();
    }
    case block::kArRpcBlockReq: {
      ArRpcBlockReq b;
      return decode_block(v, b).ok();
    }
    default:
      return false;
  }
}

}  // namespace

std::optional<PnioStatus> check_connect_blocks(std::span<const std::uint8_t> args) {
  ByteReader r(args);
  bool first = true;
  int iocrs = 0;
  while (r.remaining() >= block::kHeaderLength) {
    BlockView v;
    if (!read_block(r, v)) return connect_refusal(kCmrpc, connect_error::kCmrpcUnknownBlocks);
    const std::uint8_t code1 = block_code(v.type);
    if (code1 == 0) return connect_refusal(kCmrpc, connect_error::kCmrpcUnknownBlocks);
    if (v.type == block::kArBlockReq && !first) return connect_refusal(code1, 0x00);
    if (v.type == block::kIocrBlockReq && ++iocrs > 2)
      return connect_refusal(kCmrpc, connect_error::kCmrpcWrongBlockCount);
    if (!fields_fill_block(v)) return connect_refusal(code1, connect_error::kBlockLength);
    if (v.version_high != 1) return connect_refusal(code1, connect_error::kBlockVersionHigh);
    if (v.version_low != 0) return connect_refusal(code1, connect_error::kBlockVersionLow);
    first = false;
  }
  if (r.remaining() != 0) return connect_refusal(kCmrpc, connect_error::kCmrpcArgsLengthInvalid);
  return std::nullopt;
}

}  // namespace plc::profinet
