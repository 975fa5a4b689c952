// Cyclic RT frames (IEC 61158-6-10 §4.7 "RT", "C_SDU"; RT_CLASS_1 and
// RT_CLASS_2 frames have the same layout in their own FrameID ranges; the
// IO data object layout of §5.2.2.3 / the IOCRBlockReq):
//   Ethernet header [VLAN] 0x8892 | FrameID | C_SDU (40..1440 bytes) |
//   CycleCounter (2) | DataStatus (1) | TransferStatus (1)
// The C_SDU holds, per submodule, its IO data followed by its IOPS (an
// "IO data object"), and the IOCS the producer returns for the other
// direction's submodules; unused bytes up to the 40-byte minimum are zero.
// Encoding and decoding work on caller buffers and never allocate.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <vector>

#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/codec.hpp"
#include "plc/profinet/wire/ethernet.hpp"

namespace plc::profinet {

namespace data_status {
// DataStatus bits (IEC 61158-6-10 Table "DataStatus").
inline constexpr std::uint8_t kStatePrimary = 0x01;  // bit 0 State (1 = primary)
inline constexpr std::uint8_t kRedundancy = 0x02;
inline constexpr std::uint8_t kDataValid = 0x04;
inline constexpr std::uint8_t kProviderRun = 0x10;       // bit 4 ProviderState (1 = run)
inline constexpr std::uint8_t kStationProblemOk = 0x20;  // bit 5 (1 = normal operation)
inline constexpr std::uint8_t kIgnore = 0x80;            // bit 7 (1 = ignore)
inline constexpr std::uint8_t kGood =
    kStatePrimary | kDataValid | kProviderRun | kStationProblemOk;  // 0x35
}  // namespace data_status

// Where one submodule's bytes are in one IOCR's C_SDU.
struct IoDataObject {
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint16_t offset = 0;  // first data byte
  std::uint16_t length = 0;  // data bytes (0 for NO_IO submodules)
  [[nodiscard]] std::uint16_t iops_offset() const { return offset + length; }
};
struct IocsSlot {
  std::uint32_t api = 0;
  std::uint16_t slot = 0;
  std::uint16_t subslot = 0;
  std::uint16_t offset = 0;
};
// The layout of one IOCR (one direction).
struct IocrLayout {
  std::vector<IoDataObject> data;  // in expected-submodule order
  std::vector<IocsSlot> iocs;
  std::uint16_t c_sdu_length = iocr::kMinCSduLength;  // padded to >= 40
  [[nodiscard]] const IoDataObject* find(std::uint32_t api, std::uint16_t slot,
                                         std::uint16_t subslot) const;
  [[nodiscard]] const IocsSlot* find_iocs(std::uint32_t api, std::uint16_t slot,
                                          std::uint16_t subslot) const;
};
// Both directions. Input CR (device -> controller): an IO data object for
// every submodule with input data or no IO data at all (NO_IO submodules,
// e.g. the DAP, interface and port, get a lone IOPS), and an IOCS for every
// submodule with output data. Output CR (controller -> device): an IO data
// object for every submodule with output data, an IOCS for every submodule
// of the input CR. Data objects first, in expected order, then the IOCS.
struct CyclicLayout {
  IocrLayout input;
  IocrLayout output;
};
// Computes the layout; refuses (BadLength) a C_SDU above 1440 bytes.
WireStatus compute_layout(std::span<const ExpectedSubmoduleBlockReq> expected, CyclicLayout& out);
// The IOCRBlockReq API lists (IODataObjectFrameOffset, IOCSFrameOffset)
// and DataLength of `layout` written into `req` (its other fields kept).
void apply_layout(const IocrLayout& layout, IocrBlockReq& req);
// The layout an IOCRBlockReq describes, given the expected submodules (for
// their lengths): what a device does with a Connect request. Refuses an
// entry of no expected submodule with data in that direction, an entry
// listed twice, bytes past DataLength and two submodules' bytes that
// overlap. An expected submodule the IOCR does not list is not refused (as
// p-net does; connect_check.hpp warns); a DiscardIOXS submodule gets no
// bytes. c_sdu_length is DataLength, at least 40.
WireStatus layout_from_iocr(const IocrBlockReq& req,
                            std::span<const ExpectedSubmoduleBlockReq> expected, IocrLayout& out);

// Frame length with the given C_SDU length (header 14/18 + FrameID + C_SDU + 4).
[[nodiscard]] constexpr std::size_t cyclic_frame_length(std::size_t c_sdu_length, bool vlan) {
  return kEthernetHeaderLength + (vlan ? kVlanTagLength : 0) + 2 + c_sdu_length + 4;
}

struct CyclicHeader {
  Mac dst{};
  Mac src{};
  std::optional<std::uint16_t> vlan_tci;
  std::uint16_t frame_id = 0;
  std::uint16_t cycle_counter = 0;
  std::uint8_t data_status = data_status::kGood;
  std::uint8_t transfer_status = 0;
};
// Writes the whole frame into `out`: header, `c_sdu` (copied, then zero
// padding up to 40 bytes), APDU status. Returns the frame length, 0 if `out`
// is too small or c_sdu is longer than 1440 bytes.
std::size_t encode_cyclic(std::span<std::uint8_t> out, const CyclicHeader& h,
                          std::span<const std::uint8_t> c_sdu);
// Zero-copy variant: the C_SDU of a frame of this layout lives at
// cyclic_c_sdu(frame, ...); write the IO data there, then finish_cyclic()
// writes the header and APDU status around it. Both return empty / 0 when
// `frame` is too small.
std::span<std::uint8_t> cyclic_c_sdu(std::span<std::uint8_t> frame, std::size_t c_sdu_length,
                                     bool vlan);
std::size_t finish_cyclic(std::span<std::uint8_t> frame, const CyclicHeader& h,
                          std::size_t c_sdu_length);
// The per-frame part of a frame finish_cyclic() built once (its Ethernet
// header and FrameID stay what they are for the whole AR): writes only the
// APDU status after the C_SDU. Returns the frame length, 0 when `frame` is
// too small.
inline std::size_t put_cyclic_status(std::span<std::uint8_t> frame, std::size_t c_sdu_length,
                                     bool vlan, std::uint16_t cycle_counter,
                                     std::uint8_t data_status, std::uint8_t transfer_status) {
  const std::size_t len = cyclic_frame_length(c_sdu_length, vlan);
  if (len > frame.size()) return 0;
  std::uint8_t* p = frame.data() + len - 4;
  p[0] = static_cast<std::uint8_t>(cycle_counter >> 8);
  p[1] = static_cast<std::uint8_t>(cycle_counter);
  p[2] = data_status;
  p[3] = transfer_status;
  return len;
}

// A received cyclic frame; c_sdu views into the caller's buffer.
struct CyclicView {
  CyclicHeader header;
  std::span<const std::uint8_t> c_sdu;
};
// Parses a frame (any cyclic FrameID, is_cyclic()) whose C_SDU has
// `c_sdu_length` bytes (known from the Connect); a frame with padding beyond the APDU status (short
// frames on some NICs) is accepted, a shorter one refused. `c_sdu_length` 0: takes everything up to
// the last 4 bytes.
WireStatus decode_cyclic(std::span<const std::uint8_t> frame, std::size_t c_sdu_length,
                         CyclicView& out);
// The same for a frame whose Ethernet header is already parsed (the
// receivers look at the FrameID first): the header is not read twice.
// Inline: every cyclic frame received goes through it.
inline WireStatus decode_cyclic(const PnFrameView& v, std::size_t c_sdu_length, CyclicView& out) {
  if (!is_cyclic(v.frame_id)) return wire_fail(WireError::BadFrameId, "not a cyclic RT FrameID");
  std::size_t n = c_sdu_length;
  if (n == 0) {
    if (v.pdu.size() < iocr::kMinCSduLength + 4)
      return wire_fail(WireError::Truncated, "cyclic frame shorter than 40 + 4 bytes");
    n = v.pdu.size() - 4;
  }
  if (v.pdu.size() < n + 4)
    return wire_fail(WireError::Truncated, "cyclic frame shorter than its C_SDU");
  out.header.dst = v.dst;
  out.header.src = v.src;
  out.header.vlan_tci = v.vlan_tci;
  out.header.frame_id = v.frame_id;
  out.c_sdu = v.pdu.first(n);
  const std::uint8_t* s = v.pdu.data() + n;
  out.header.cycle_counter = static_cast<std::uint16_t>(s[0] << 8 | s[1]);
  out.header.data_status = s[2];
  out.header.transfer_status = s[3];
  return kWireOk;
}

// Cycle counter rule of p-net/IEC 61158-6-10: a new frame's counter is
// ahead of the previous one by 1..61440 (mod 65536); equal = duplicate.
[[nodiscard]] constexpr bool cycle_counter_advanced(std::uint16_t previous, std::uint16_t now) {
  const auto d = static_cast<std::uint16_t>(now - previous);
  return d >= 1 && d <= 61440;
}

// Copies the n bytes of one IO data object or device image (a few to a few
// dozen bytes, per frame or scan) in place, without a call into libc's
// memcpy, whose call costs more than the copy at these sizes: two moves of
// 16, 8, 4 or 2 bytes that overlap in the middle (both loaded before either
// is stored), one byte, or memcpy above 32 bytes. The same bytes as memcpy.
[[gnu::always_inline]] inline void copy_io_bytes(std::uint8_t* dst, const std::uint8_t* src,
                                                 std::size_t n) {
  const auto two = [&]<std::size_t W>() {
    unsigned char a[W], b[W];
    std::memcpy(a, src, W);
    std::memcpy(b, src + n - W, W);
    std::memcpy(dst, a, W);
    std::memcpy(dst + n - W, b, W);
  };
  if (n > 32) {
    std::memcpy(dst, src, n);
  } else if (n >= 16) {
    two.template operator()<16>();
  } else if (n >= 8) {
    two.template operator()<8>();
  } else if (n >= 4) {
    two.template operator()<4>();
  } else if (n >= 2) {
    two.template operator()<2>();
  } else if (n == 1) {
    dst[0] = src[0];
  }
}

// Accessors of one IO data object inside a C_SDU (no bounds beyond the
// layout's own: the layout is checked once when computed). Inline: every
// cyclic frame, sent or received, goes through them.
inline void put_io_data(std::span<std::uint8_t> c_sdu, const IoDataObject& o,
                        std::span<const std::uint8_t> data, std::uint8_t iops_value) {
  if (std::size_t{o.offset} + o.length + 1 > c_sdu.size()) return;
  const std::size_t n = std::min<std::size_t>(data.size(), o.length);
  copy_io_bytes(c_sdu.data() + o.offset, data.data(), n);
  if (n < o.length)  // mostly not: the data is the object's length
    std::fill_n(c_sdu.begin() + o.offset + static_cast<std::ptrdiff_t>(n), o.length - n,
                std::uint8_t{0});
  c_sdu[o.iops_offset()] = iops_value;
}
inline std::span<const std::uint8_t> io_data(std::span<const std::uint8_t> c_sdu,
                                             const IoDataObject& o) {
  if (std::size_t{o.offset} + o.length + 1 > c_sdu.size()) return {};
  return c_sdu.subspan(o.offset, o.length);
}
inline std::uint8_t iops(std::span<const std::uint8_t> c_sdu, const IoDataObject& o) {
  if (std::size_t{o.offset} + o.length + 1 > c_sdu.size()) return iocr::kIoxsBad;
  return c_sdu[o.iops_offset()];
}

}  // namespace plc::profinet
