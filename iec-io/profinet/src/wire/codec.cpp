#include "plc/profinet/wire/codec.hpp"

#include <algorithm>
#include <cstring>

namespace plc::profinet {

const char* to_string(WireError e) {
  switch (e) {
    case WireError::None:
      return "ok";
    case WireError::Truncated:
      return "truncated";
    case WireError::BadLength:
      return "bad length";
    case WireError::BadBlockType:
      return "bad block type";
    case WireError::BadBlockVersion:
      return "bad block version";
    case WireError::BadHeader:
      return "bad header";
    case WireError::BadFrameId:
      return "bad frame id";
    case WireError::BadEtherType:
      return "bad ethertype";
    case WireError::BadValue:
      return "bad value";
    case WireError::BufferTooSmall:
      return "buffer too small";
  }
  return "?";
}

bool ByteReader::take(std::size_t n) {
  if (failed_ || n > b_.size() - pos_) {
    failed_ = true;
    return false;
  }
  return true;
}

std::uint8_t ByteReader::u8() {
  if (!take(1)) return 0;
  return b_[pos_++];
}

std::uint16_t ByteReader::u16(bool little_endian) {
  if (!take(2)) return 0;
  const std::uint16_t a = b_[pos_], b = b_[pos_ + 1];
  pos_ += 2;
  return static_cast<std::uint16_t>(little_endian ? (b << 8) | a : (a << 8) | b);
}

std::uint32_t ByteReader::u32(bool little_endian) {
  if (!take(4)) return 0;
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) {
    const std::uint32_t byte = b_[pos_ + static_cast<std::size_t>(i)];
    v |= little_endian ? byte << (8 * i) : byte << (8 * (3 - i));
  }
  pos_ += 4;
  return v;
}

std::uint16_t ByteReader::u16() { return u16(false); }
std::uint32_t ByteReader::u32() { return u32(false); }

std::span<const std::uint8_t> ByteReader::bytes(std::size_t n) {
  if (!take(n)) return {};
  auto s = b_.subspan(pos_, n);
  pos_ += n;
  return s;
}

std::uint8_t* ByteWriter::take(std::size_t n) {
  if (failed_ || n > b_.size() - pos_) {
    failed_ = true;
    return nullptr;
  }
  std::uint8_t* p = b_.data() + pos_;
  pos_ += n;
  return p;
}

void ByteWriter::u8(std::uint8_t v) {
  if (auto* p = take(1)) p[0] = v;
}
void ByteWriter::u16(std::uint16_t v) { u16(v, false); }
void ByteWriter::u32(std::uint32_t v) { u32(v, false); }
void ByteWriter::u16(std::uint16_t v, bool little_endian) {
  if (auto* p = take(2)) {
    p[little_endian ? 1 : 0] = static_cast<std::uint8_t>(v >> 8);
    p[little_endian ? 0 : 1] = static_cast<std::uint8_t>(v);
  }
}
void ByteWriter::u32(std::uint32_t v, bool little_endian) {
  if (auto* p = take(4)) {
    for (int i = 0; i < 4; ++i) {
      const int shift = little_endian ? 8 * i : 8 * (3 - i);
      p[i] = static_cast<std::uint8_t>(v >> shift);
    }
  }
}
void ByteWriter::bytes(std::span<const std::uint8_t> v) {
  if (auto* p = take(v.size()); p && !v.empty()) std::copy(v.begin(), v.end(), p);
}
void ByteWriter::zeros(std::size_t n) {
  if (auto* p = take(n)) std::fill_n(p, n, std::uint8_t{0});
}
void ByteWriter::patch_u16(std::size_t at, std::uint16_t v) {
  if (at + 2 > pos_) {
    failed_ = true;
    return;
  }
  b_[at] = static_cast<std::uint8_t>(v >> 8);
  b_[at + 1] = static_cast<std::uint8_t>(v);
}
void ByteWriter::patch_u32(std::size_t at, std::uint32_t v, bool little_endian) {
  if (at + 4 > pos_) {
    failed_ = true;
    return;
  }
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t shift = little_endian ? 8 * i : 8 * (3 - i);
    b_[at + i] = static_cast<std::uint8_t>(v >> shift);
  }
}

void ByteBuilder::patch_u16(std::size_t at, std::uint16_t v, bool little_endian) {
  out_.at(at + (little_endian ? 1 : 0)) = static_cast<std::uint8_t>(v >> 8);
  out_.at(at + (little_endian ? 0 : 1)) = static_cast<std::uint8_t>(v);
}
void ByteBuilder::patch_u32(std::size_t at, std::uint32_t v, bool little_endian) {
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t shift = little_endian ? 8 * i : 8 * (3 - i);
    out_.at(at + i) = static_cast<std::uint8_t>(v >> shift);
  }
}
void ByteBuilder::bytes(std::span<const std::uint8_t> v) {
  const std::size_t at = out_.size();
  out_.resize(at + v.size());
  if (!v.empty()) std::memcpy(out_.data() + at, v.data(), v.size());
}
void ByteBuilder::align(std::size_t a, std::size_t from) {
  while ((out_.size() - from) % a != 0) out_.push_back(0);
}

}  // namespace plc::profinet
