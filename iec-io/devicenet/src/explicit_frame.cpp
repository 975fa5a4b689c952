#include "plc/devicenet/explicit_frame.hpp"

#include <algorithm>

#include "plc/devicenet/identifiers.hpp"

namespace plc::devicenet {

bool build_explicit(std::uint16_t id, std::uint8_t header_mac, bool xid,
                    std::span<const std::uint8_t> msg, ExplicitFrames& out) {
  out.count = 0;
  if (msg.empty() || msg.size() > kMaxExplicitMessage) return false;
  const std::uint8_t hdr = static_cast<std::uint8_t>((xid ? kXidBit : 0) | (header_mac & 0x3F));
  if (msg.size() <= 7) {
    can::Frame& f = out.frames[0];
    f = {};
    f.id = id;
    f.data[0] = hdr;
    std::copy(msg.begin(), msg.end(), f.data.begin() + 1);
    f.len = static_cast<std::uint8_t>(1 + msg.size());
    out.count = 1;
    return true;
  }
  std::size_t pos = 0;
  while (pos < msg.size()) {
    const std::size_t n = std::min(kExplicitFragmentData, msg.size() - pos);
    const bool last = pos + n == msg.size();
    const FragType t = out.count == 0 ? FragType::First : last ? FragType::Last : FragType::Middle;
    can::Frame& f = out.frames[out.count];
    f = {};
    f.id = id;
    f.data[0] = static_cast<std::uint8_t>(hdr | kFragBit);
    f.data[1] = frag_byte(t, static_cast<std::uint8_t>(out.count));
    std::copy_n(msg.begin() + static_cast<std::ptrdiff_t>(pos), n, f.data.begin() + 2);
    f.len = static_cast<std::uint8_t>(2 + n);
    ++out.count;
    pos += n;
  }
  return true;
}

can::Frame explicit_ack(std::uint16_t id, std::uint8_t header_mac, bool xid, std::uint8_t count,
                        std::uint8_t status) {
  can::Frame f;
  f.id = id;
  f.data[0] = static_cast<std::uint8_t>(kFragBit | (xid ? kXidBit : 0) | (header_mac & 0x3F));
  f.data[1] = frag_byte(FragType::Ack, count);
  f.data[2] = status;
  f.len = 3;
  return f;
}

ExplicitReassembler::Result ExplicitReassembler::take(const can::Frame& f) {
  if (f.len < 2 || f.len > 8) return Result::Bad;
  const std::uint8_t hdr = f.data[0];
  mac_ = hdr & 0x3F;
  xid_ = (hdr & kXidBit) != 0;
  if (!(hdr & kFragBit)) {
    in_progress_ = false;
    len_ = f.len - 1u;
    std::copy_n(f.data.begin() + 1, len_, buf_.begin());
    return Result::Message;
  }
  const std::uint8_t fb = f.data[1];
  const std::uint8_t count = frag_count(fb);
  const std::size_t n = f.len - 2u;
  switch (frag_type(fb)) {
    case FragType::Ack:
      if (f.len < 3) return Result::Bad;
      ack_count_ = count;
      ack_status_ = f.data[2];
      return Result::AckReceived;
    case FragType::First:
      if (n == 0) return Result::Bad;
      len_ = 0;
      in_progress_ = true;
      break;
    case FragType::Middle:
    case FragType::Last:
      if (!in_progress_ || n == 0) {
        reset();
        return Result::Bad;
      }
      if (count == static_cast<std::uint8_t>((next_count_ - 1) & 0x3F)) {
        ack_count_ = count;  // a repeat of the fragment we took last: its ack was lost
        return Result::FragmentAck;
      }
      if (count != next_count_) {
        reset();
        return Result::Bad;
      }
      break;
  }
  if (len_ + n > buf_.size()) {
    reset();
    return Result::Bad;
  }
  std::copy_n(f.data.begin() + 2, n, buf_.begin() + static_cast<std::ptrdiff_t>(len_));
  len_ += n;
  next_count_ = static_cast<std::uint8_t>((count + 1) & 0x3F);
  ack_count_ = count;
  if (frag_type(fb) == FragType::Last) {
    in_progress_ = false;
    return Result::LastFragment;
  }
  return Result::FragmentAck;
}

bool build_io(std::uint16_t id, std::span<const std::uint8_t> data, IoFrames& out) {
  out.count = 0;
  if (data.size() <= 8) {
    can::Frame& f = out.frames[0];
    f = {};
    f.id = id;
    f.len = static_cast<std::uint8_t>(data.size());
    std::copy(data.begin(), data.end(), f.data.begin());
    out.count = 1;
    return true;
  }
  if (data.size() > out.frames.size() * kIoFragmentData) return false;
  std::size_t pos = 0;
  while (pos < data.size()) {
    const std::size_t n = std::min(kIoFragmentData, data.size() - pos);
    const bool last = pos + n == data.size();
    const FragType t = out.count == 0 ? FragType::First : last ? FragType::Last : FragType::Middle;
    can::Frame& f = out.frames[out.count];
    f = {};
    f.id = id;
    f.data[0] = frag_byte(t, static_cast<std::uint8_t>(out.count));
    std::copy_n(data.begin() + static_cast<std::ptrdiff_t>(pos), n, f.data.begin() + 1);
    f.len = static_cast<std::uint8_t>(1 + n);
    ++out.count;
    pos += n;
  }
  return true;
}

IoReassembler::Result IoReassembler::take(const can::Frame& f) {
  if (f.len > 8) return Result::Bad;
  if (expected_ <= 8) {
    len_ = f.len;
    std::copy_n(f.data.begin(), f.len, buf_.begin());
    return Result::Complete;
  }
  if (f.len < 2) {
    reset();
    return Result::Bad;
  }
  const std::uint8_t fb = f.data[0];
  const std::uint8_t count = frag_count(fb);
  const std::size_t n = f.len - 1u;
  switch (frag_type(fb)) {
    case FragType::First:
      if (count != 0) {
        reset();
        return Result::Bad;
      }
      len_ = 0;
      in_progress_ = true;
      break;
    case FragType::Middle:
    case FragType::Last:
      if (!in_progress_ || count != next_count_) {
        reset();
        return Result::Bad;
      }
      break;
    case FragType::Ack:
      reset();
      return Result::Bad;  // I/O fragments are never acknowledged
  }
  if (len_ + n > buf_.size()) {
    reset();
    return Result::Bad;
  }
  std::copy_n(f.data.begin() + 1, n, buf_.begin() + static_cast<std::ptrdiff_t>(len_));
  len_ += n;
  next_count_ = static_cast<std::uint8_t>((count + 1) & 0x3F);
  if (frag_type(fb) == FragType::Last) {
    in_progress_ = false;
    return Result::Complete;
  }
  return Result::Partial;
}

can::Frame build_dup_mac(std::uint8_t mac, const DupMac& m) {
  can::Frame f;
  f.id = group2_id(mac, kG2DupMac);
  f.data[0] = static_cast<std::uint8_t>((m.response ? 0x80 : 0) | (m.port & 0x7F));
  f.data[1] = static_cast<std::uint8_t>(m.vendor);
  f.data[2] = static_cast<std::uint8_t>(m.vendor >> 8);
  for (int i = 0; i < 4; ++i) f.data[3 + i] = static_cast<std::uint8_t>(m.serial >> (8 * i));
  f.len = 7;
  return f;
}

std::optional<DupMac> parse_dup_mac(const can::Frame& f) {
  if (f.len != 7) return std::nullopt;
  DupMac m;
  m.response = (f.data[0] & 0x80) != 0;
  m.port = f.data[0] & 0x7F;
  m.vendor = static_cast<std::uint16_t>(f.data[1] | (f.data[2] << 8));
  m.serial = std::uint32_t(f.data[3]) | (std::uint32_t(f.data[4]) << 8) |
             (std::uint32_t(f.data[5]) << 16) | (std::uint32_t(f.data[6]) << 24);
  return m;
}

}  // namespace plc::devicenet
