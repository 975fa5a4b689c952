// The receiving side of LCM's udpm wire format (udpm_wire.hpp): datagrams
// in, complete messages out, with every length, offset and count checked
// before it is used. It replaces liblcm 1.3.1's receive path in the bridge
// and plcctl: there, a fragment whose fragment_offset + size wraps past
// 2^32 (e.g. offset 0xFFFFFFF0, 32 bytes) passes the bounds check and
// memcpy writes 4 GiB past the buffer (lcm_udpm.c:316-324; upstream
// lcm-proj/lcm pull request 628): one 60-byte datagram killed plcrun
// (issue 22). Here a hostile datagram is counted by its reason and dropped.
//
// As liblcm: one reassembly per sender (source address and port), started
// by fragment 0 (which names the channel) and only for a channel someone
// subscribes to; a fragment of another message (seqno, msg_size or
// n_fragments differ) from the same sender abandons the one in progress.
// Unlike liblcm: the number of reassemblies and their bytes together are
// bounded (the least recently fed one is evicted to make room, a stale one
// first), a message is complete only when every fragment number arrived
// once and their pieces tile the message exactly (duplicates are dropped,
// never counted twice), and nothing is allocated for a claimed size above
// the configured maximum.
//
// Single-threaded: the transport's handling thread owns it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "plc/hmi/transport_counters.hpp"

namespace plc::hmi {

struct UdpmLimits {
  // The largest message accepted (and sent): checked_decode's bound.
  std::size_t max_message_bytes = std::size_t(1) << 22;
  // Reassemblies in progress at once (one per sender).
  std::size_t max_senders = 64;
  // Their buffers and bookkeeping together (liblcm's MAX_FRAG_BUF_TOTAL_SIZE,
  // udpm_util.h:51, 16 MiB); at least one message of the maximum size.
  std::size_t max_reassembly_bytes = std::size_t(1) << 24;
  // A reassembly not fed for this long is evicted first when room is needed.
  std::int64_t reassembly_timeout_us = 2'000'000;
};

// One complete message: valid until the next take().
struct UdpmMessage {
  std::string_view channel;
  std::span<const std::uint8_t> data;
  std::int64_t recv_utime = 0;
};

class UdpmReceiver {
 public:
  // wanted(channel): whether a subscription matches (messages nobody wants
  // are neither reassembled nor returned).
  using Wanted = std::function<bool(std::string_view channel)>;
  UdpmReceiver(const UdpmLimits& limits, Wanted wanted);

  // One datagram from `sender` (address << 16 | port). now_us: a monotonic
  // clock (staleness); recv_utime: its arrival on the wall clock (a
  // fragmented message gets its last fragment's, as liblcm). Returns the
  // message it completes, if any. Never throws.
  std::optional<UdpmMessage> take(std::span<const std::uint8_t> datagram, std::uint64_t sender,
                                  std::int64_t now_us, std::int64_t recv_utime) noexcept;

  // A datagram the socket cut short (MSG_TRUNC): counted, never parsed.
  void count_truncated() {
    ++counters_.datagrams;
    ++counters_.truncated;
  }

  [[nodiscard]] const TransportCounters& counters() const { return counters_; }
  [[nodiscard]] TransportCounters& counters() { return counters_; }
  [[nodiscard]] std::size_t reassemblies() const { return open_.size(); }
  // What the reassemblies in progress hold (counted against max_reassembly_bytes).
  [[nodiscard]] std::size_t reassembly_bytes() const { return bytes_; }
  [[nodiscard]] const UdpmLimits& limits() const { return limits_; }

 private:
  struct Piece {
    std::uint32_t offset, size;
  };
  struct Reassembly {
    std::uint64_t sender = 0;
    std::uint32_t seqno = 0, msg_size = 0;
    std::uint16_t n_fragments = 0;
    std::uint32_t received = 0;  // fragments
    std::int64_t last_us = 0;
    std::size_t cost = 0;
    std::string channel;
    std::vector<std::uint8_t> data;
    std::vector<std::uint64_t> seen;  // one bit per fragment number
    std::vector<Piece> pieces;
  };
  std::optional<UdpmMessage> take_short(std::span<const std::uint8_t> d, std::int64_t recv_utime);
  std::optional<UdpmMessage> take_fragment(std::span<const std::uint8_t> d, std::uint64_t sender,
                                           std::int64_t now_us, std::int64_t recv_utime);
  // The channel at the start of `body`: its length (NUL excluded), or -1
  // after counting why not.
  int channel_length(std::span<const std::uint8_t> body);
  Reassembly* start(std::uint64_t sender, std::uint32_t seqno, std::uint32_t msg_size,
                    std::uint16_t n_fragments, std::string_view channel, std::int64_t now_us);
  void remove(std::size_t index);

  UdpmLimits limits_;
  Wanted wanted_;
  TransportCounters counters_;
  std::vector<Reassembly> open_;
  std::size_t bytes_ = 0;
  std::string done_channel_;  // the last completed fragmented message
  std::vector<std::uint8_t> done_data_;
};

}  // namespace plc::hmi
