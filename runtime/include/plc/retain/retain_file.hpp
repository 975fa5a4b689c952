// The retain file format (format version 1), all integers little-endian:
//
//   offset  size  field
//   0       8     magic "PLCRET01"
//   8       4     format version (1)
//   12      4     number of entries
//   16      8     layout hash (Layout::hash: paths, types and sizes)
//   24      8     sequence number (1, 2, ... per cell; the newest copy wins)
//   32      8     saved at: Unix time in ns (CLOCK_REALTIME; for the report)
//   40      8     file length in bytes, CRC included (a cut file is caught
//                 before its CRC is even looked at)
//   48      ...   entries: u16 path length, path (UTF-8), u8 type (VarType
//                 code, or 0xFE for a %M byte range), u32 value size, value
//                 (the host's native representation; STRING: a length
//                 byte and the 80 characters, zero-padded)
//   end-4   4     CRC-32 (boost::crc_32_type, IEEE 802.3) over all bytes
//                 before it
//
// Entries carry their path and type so that a program whose layout changed
// restores what still matches (path, type and size) and nothing else.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "plc/retain/retain_layout.hpp"

namespace plc::retain {

inline constexpr char kMagic[8] = {'P', 'L', 'C', 'R', 'E', 'T', '0', '1'};
inline constexpr std::uint32_t kFormatVersion = 1;
inline constexpr std::size_t kHeaderBytes = 48;

struct FileEntry {
  std::string path;
  std::uint8_t type = 0;
  std::vector<std::uint8_t> value;
};

struct FileImage {
  std::uint64_t layout_hash = 0;
  std::uint64_t sequence = 0;
  std::int64_t saved_unix_ns = 0;
  std::vector<FileEntry> entries;
};

// Serialises `snapshot` (Layout::bytes() long) into `out`, which keeps its
// capacity from one call to the next (the writer thread reuses it).
void encode(const Layout& layout, std::span<const std::uint8_t> snapshot, std::uint64_t sequence,
            std::int64_t saved_unix_ns, std::vector<std::uint8_t>& out);

// Checks and parses a file's bytes; nullopt and `error` (why) for anything
// but a complete, undamaged file of this format.
std::optional<FileImage> decode(std::span<const std::uint8_t> bytes, std::string& error);

}  // namespace plc::retain
