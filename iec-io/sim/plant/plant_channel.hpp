// How one input or output of the `plant` model meets bytes: its IEC type
// and byte order, the raw <-> engineering scaling and saturation
// (plc/sim/plant/channel_scaling.hpp), and where its bytes are: the plant's
// own area in the image, or another device's (plc/io/device_peers.hpp).
//
// Parsed from a channel's keys (`u1.type`, `u1.raw`, ...; docs/config.md,
// "The plant model"). Decoding and encoding run in the model's step: no
// allocation, no exception.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "plc/io/byte_order.hpp"
#include "plc/io/device_peers.hpp"
#include "plc/io/model_params.hpp"
#include "plc/sim/plant/channel_scaling.hpp"
#include "plc/types.hpp"

namespace plc::plant {

enum class ChannelType : std::uint8_t { BOOL, SINT, USINT, INT, UINT, DINT, UDINT, REAL, LREAL };

[[nodiscard]] std::size_t type_size(ChannelType t);

// Where a channel's bytes are: the plant's own process data (`device`
// empty), or `byte` in another device's inputs (device -> PLC) or outputs
// (PLC -> device).
struct ChannelPlace {
  std::string device;
  bool peer_outputs = false;
  std::size_t byte = 0;
  std::span<std::uint8_t> bytes;  // bound: own area or the peer's; empty until bound
};

struct ChannelCodec {
  ChannelType type = ChannelType::INT;
  io::ByteOrder order = io::ByteOrder::Big;
  LinearScale scale;
  Saturation saturation;

  // The value in engineering units, saturated (NaN of a REAL source passes
  // as NaN: the model checks).
  [[nodiscard]] double decode(const std::uint8_t* p) const;
  // Engineering value -> raw: saturated, scaled, rounded half away from
  // zero for integer types and limited to the type's range; a BOOL is TRUE
  // from 0.5 of its raw range up.
  void encode(double eng, std::uint8_t* p) const;
};

// Reads `prefix.type`, `.raw`, `.eng`, `.min`, `.max`, `.order` (defaults:
// INT with the S7 analog scaling 0..27648 = 0..100 and saturation to that
// range; BOOL 0/1 = 0/100; REAL and LREAL unscaled and unsaturated).
// Throws ParamError naming the key.
ChannelCodec parse_codec(const io::ModelParams& p, const std::string& prefix, io::ByteOrder order);

}  // namespace plc::plant
