#include "plc/retain/retain_file.hpp"

#include <boost/crc.hpp>
#include <boost/endian/conversion.hpp>
#include <cstring>

namespace plc::retain {
namespace {

template <class U>
void put_at(std::uint8_t* p, U v) {
  const U le = boost::endian::native_to_little(v);
  std::memcpy(p, &le, sizeof le);
}

template <class U>
void put(std::vector<std::uint8_t>& out, U v) {
  out.resize(out.size() + sizeof v);
  put_at(out.data() + out.size() - sizeof v, v);
}

template <class U>
U get(const std::uint8_t* p) {
  U v;
  std::memcpy(&v, p, sizeof v);
  return boost::endian::little_to_native(v);
}

std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
  boost::crc_32_type crc;
  crc.process_bytes(p, n);
  return crc.checksum();
}

}  // namespace

void encode(const Layout& layout, std::span<const std::uint8_t> snapshot, std::uint64_t sequence,
            std::int64_t saved_unix_ns, std::vector<std::uint8_t>& out) {
  out.resize(kHeaderBytes);
  std::memcpy(out.data(), kMagic, sizeof kMagic);
  put_at<std::uint32_t>(out.data() + 8, kFormatVersion);
  put_at<std::uint32_t>(out.data() + 12, static_cast<std::uint32_t>(layout.entries().size()));
  put_at<std::uint64_t>(out.data() + 16, layout.hash());
  put_at<std::uint64_t>(out.data() + 24, sequence);
  put_at<std::int64_t>(out.data() + 32, saved_unix_ns);
  for (const Entry& e : layout.entries()) {
    put<std::uint16_t>(out, static_cast<std::uint16_t>(e.path.size()));
    const std::size_t at = out.size();
    out.resize(at + e.path.size() + 1);
    std::memcpy(out.data() + at, e.path.data(), e.path.size());
    out[at + e.path.size()] = e.type;
    put<std::uint32_t>(out, static_cast<std::uint32_t>(e.size));
    const std::size_t v = out.size();
    out.resize(v + e.size);
    std::memcpy(out.data() + v, snapshot.data() + e.offset, e.size);
  }
  put_at<std::uint64_t>(out.data() + 40, out.size() + 4);  // the length, CRC included
  put<std::uint32_t>(out, crc32(out.data(), out.size()));
}

std::optional<FileImage> decode(std::span<const std::uint8_t> b, std::string& error) {
  if (b.size() < kHeaderBytes + 4) {
    error = "cut off: " + std::to_string(b.size()) + " bytes, shorter than a header";
    return std::nullopt;
  }
  if (std::memcmp(b.data(), kMagic, sizeof kMagic) != 0) {
    error = "not a retain file (no PLCRET01 magic)";
    return std::nullopt;
  }
  const auto version = get<std::uint32_t>(b.data() + 8);
  if (version != kFormatVersion) {
    error = "format version " + std::to_string(version) + " (this plcrun reads version " +
            std::to_string(kFormatVersion) + ")";
    return std::nullopt;
  }
  const auto length = get<std::uint64_t>(b.data() + 40);
  if (length != b.size()) {
    error = "cut off or extended: " + std::to_string(b.size()) + " bytes, the header says " +
            std::to_string(length);
    return std::nullopt;
  }
  const std::size_t body = b.size() - 4;
  if (crc32(b.data(), body) != get<std::uint32_t>(b.data() + body)) {
    error = "CRC mismatch (damaged)";
    return std::nullopt;
  }
  FileImage img;
  const auto count = get<std::uint32_t>(b.data() + 12);
  img.layout_hash = get<std::uint64_t>(b.data() + 16);
  img.sequence = get<std::uint64_t>(b.data() + 24);
  img.saved_unix_ns = get<std::int64_t>(b.data() + 32);
  // Each entry takes at least 7 bytes: a count beyond that is a lie that
  // must not reserve memory.
  if (count > (body - kHeaderBytes) / 7) {
    error = "entry count " + std::to_string(count) + " does not fit the file";
    return std::nullopt;
  }
  img.entries.reserve(count);
  std::size_t p = kHeaderBytes;
  for (std::uint32_t i = 0; i < count; ++i) {
    if (p + 2 > body) break;
    const std::size_t plen = get<std::uint16_t>(b.data() + p);
    p += 2;
    if (p + plen + 5 > body) break;
    FileEntry e;
    e.path.assign(reinterpret_cast<const char*>(b.data() + p), plen);
    p += plen;
    e.type = b[p++];
    const std::size_t vlen = get<std::uint32_t>(b.data() + p);
    p += 4;
    if (vlen > body - p) break;
    e.value.assign(b.data() + p, b.data() + p + vlen);
    p += vlen;
    img.entries.push_back(std::move(e));
  }
  if (img.entries.size() != count || p != body) {
    error = "entries do not match the header (damaged)";
    return std::nullopt;
  }
  return img;
}

}  // namespace plc::retain
