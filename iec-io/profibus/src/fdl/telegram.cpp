#include "plc/profibus/fdl/telegram.hpp"

#include <algorithm>

namespace plc::profibus::fdl {

const char* to_string(Format f) {
  switch (f) {
    case Format::Sd1:
      return "SD1";
    case Format::Sd2:
      return "SD2";
    case Format::Sd3:
      return "SD3";
    case Format::Token:
      return "SD4";
    case Format::ShortAck:
      return "SC";
  }
  return "?";
}

namespace {

std::size_t extension_bytes(const Telegram& t) {
  return static_cast<std::size_t>((t.dsap >= 0) + (t.dseg >= 0) + (t.ssap >= 0) + (t.sseg >= 0));
}

// Writes one address's extension bytes (segment first, then the SAP).
std::size_t put_extension(std::int16_t seg, std::int16_t sap, std::uint8_t* p) {
  std::size_t n = 0;
  if (seg >= 0) p[n++] = static_cast<std::uint8_t>(0x40 | seg | (sap >= 0 ? 0x80 : 0));
  if (sap >= 0) p[n++] = static_cast<std::uint8_t>(sap);
  return n;
}

// Reads one address's extension bytes at `p` (up to `end`): the SAP and the
// segment address; returns the bytes read, 0 when malformed.
std::size_t get_extension(const std::uint8_t* p, const std::uint8_t* end, std::int16_t& seg,
                          std::int16_t& sap) {
  std::size_t n = 0;
  for (;;) {
    if (p + n >= end || n >= 2) return 0;  // at most one segment byte and one SAP
    const std::uint8_t b = p[n++];
    if (b & 0x40) {
      if (seg >= 0) return 0;
      seg = b & 0x3F;
    } else {
      if (sap >= 0) return 0;
      sap = b & 0x3F;
    }
    if (!(b & 0x80)) return n;
  }
}

}  // namespace

bool Telegram::set_data(std::span<const std::uint8_t> d) {
  if (d.size() + extension_bytes(*this) > kMaxDataUnit) return false;
  std::copy(d.begin(), d.end(), data.begin());
  length = static_cast<std::uint8_t>(d.size());
  return true;
}

Telegram make_data(std::uint8_t da, std::uint8_t sa, std::uint8_t fc, std::int16_t dsap,
                   std::int16_t ssap, std::span<const std::uint8_t> d) {
  Telegram t;
  t.format = Format::Sd2;
  t.da = da;
  t.sa = sa;
  t.fc = fc;
  t.dsap = dsap;
  t.ssap = ssap;
  t.set_data(d);
  return t;
}

Telegram make_token(std::uint8_t da, std::uint8_t sa) {
  Telegram t;
  t.format = Format::Token;
  t.da = da;
  t.sa = sa;
  return t;
}

Telegram make_short_ack() {
  Telegram t;
  t.format = Format::ShortAck;
  return t;
}

std::uint8_t fcs(std::span<const std::uint8_t> bytes) {
  std::uint8_t s = 0;
  for (const std::uint8_t b : bytes) s = static_cast<std::uint8_t>(s + b);
  return s;
}

std::size_t encode(const Telegram& t, std::span<std::uint8_t> out) {
  if (t.format == Format::ShortAck) {
    if (out.empty()) return 0;
    out[0] = kSc;
    return 1;
  }
  if (t.da > 127 || t.sa > 127) return 0;
  if (t.format == Format::Token) {
    if (out.size() < 3) return 0;
    out[0] = kSd4;
    out[1] = t.da;
    out[2] = t.sa;
    return 3;
  }
  if (t.dsap > 63 || t.ssap > 63 || t.dseg > 63 || t.sseg > 63) return 0;
  const bool dae = t.dsap >= 0 || t.dseg >= 0;
  const bool sae = t.ssap >= 0 || t.sseg >= 0;
  const std::size_t unit = extension_bytes(t) + t.length;
  if (unit > kMaxDataUnit) return 0;
  const std::size_t head = unit == 0 ? 1 : unit == 8 ? 1 : 4;
  const std::size_t total = head + 3 + unit + 2;
  if (out.size() < total) return 0;
  std::uint8_t* p = out.data();
  if (unit == 0) {
    *p++ = kSd1;
  } else if (unit == 8) {
    *p++ = kSd3;
  } else {
    *p++ = kSd2;
    *p++ = static_cast<std::uint8_t>(unit + 3);
    *p++ = static_cast<std::uint8_t>(unit + 3);
    *p++ = kSd2;
  }
  std::uint8_t* const body = p;
  *p++ = static_cast<std::uint8_t>(t.da | (dae ? kAddressExt : 0));
  *p++ = static_cast<std::uint8_t>(t.sa | (sae ? kAddressExt : 0));
  *p++ = t.fc;
  p += put_extension(t.dseg, t.dsap, p);
  p += put_extension(t.sseg, t.ssap, p);
  p = std::copy_n(t.data.begin(), t.length, p);
  *p = fcs({body, static_cast<std::size_t>(p - body)});
  ++p;
  *p++ = kEd;
  return static_cast<std::size_t>(p - out.data());
}

namespace {

DecodeResult bad(const char* why) { return {DecodeStatus::Bad, 0, why}; }

// DA SA FC [ext] DU at `body` (n bytes), then FCS and ED.
DecodeResult decode_body(std::span<const std::uint8_t> in, std::size_t head, std::size_t n,
                         Format f, Telegram& t) {
  const std::size_t total = head + n + 2;
  if (in.size() < total) return {DecodeStatus::NeedMore, 0, ""};
  const std::uint8_t* body = in.data() + head;
  if (in[head + n + 1] != kEd) return bad("no end delimiter");
  if (fcs({body, n}) != in[head + n]) return bad("frame check sequence");
  t = Telegram{};
  t.format = f;
  t.da = body[0] & 0x7F;
  t.sa = body[1] & 0x7F;
  t.fc = body[2];
  const std::uint8_t* p = body + 3;
  const std::uint8_t* end = body + n;
  if (body[0] & kAddressExt) {
    const std::size_t k = get_extension(p, end, t.dseg, t.dsap);
    if (k == 0) return bad("address extension of DA");
    p += k;
  }
  if (body[1] & kAddressExt) {
    const std::size_t k = get_extension(p, end, t.sseg, t.ssap);
    if (k == 0) return bad("address extension of SA");
    p += k;
  }
  t.length = static_cast<std::uint8_t>(end - p);
  std::copy(p, end, t.data.begin());
  return {DecodeStatus::Ok, total, ""};
}

}  // namespace

DecodeResult decode(std::span<const std::uint8_t> in, Telegram& t) {
  if (in.empty()) return {DecodeStatus::NeedMore, 0, ""};
  switch (in[0]) {
    case kSc:
      t = Telegram{};
      t.format = Format::ShortAck;
      return {DecodeStatus::Ok, 1, ""};
    case kSd4:
      if (in.size() < 3) return {DecodeStatus::NeedMore, 0, ""};
      if ((in[1] | in[2]) & kAddressExt) return bad("token address above 127");
      t = Telegram{};
      t.format = Format::Token;
      t.da = in[1];
      t.sa = in[2];
      return {DecodeStatus::Ok, 3, ""};
    case kSd1: {
      auto r = decode_body(in, 1, 3, Format::Sd1, t);
      if (r.status == DecodeStatus::Ok && ((in[1] | in[2]) & kAddressExt))
        return bad("SD1 with an address extension");
      return r;
    }
    case kSd3:
      return decode_body(in, 1, 11, Format::Sd3, t);
    case kSd2: {
      if (in.size() < 4) {
        if (in.size() >= 3 && in[1] != in[2]) return bad("LE and LEr differ");
        return {DecodeStatus::NeedMore, 0, ""};
      }
      if (in[1] != in[2]) return bad("LE and LEr differ");
      if (in[3] != kSd2) return bad("second start delimiter");
      if (in[1] < 4 || in[1] > 249) return bad("LE outside 4..249");
      return decode_body(in, 4, in[1], Format::Sd2, t);
    }
    default:
      return bad("no start delimiter");
  }
}

}  // namespace plc::profibus::fdl
