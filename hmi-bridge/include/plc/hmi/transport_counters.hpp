// What an HMI transport received, delivered and dropped, by reason. The
// bridge publishes them in stats_t (plcctl stats prints the ones not zero).
//
// Every datagram received ends in exactly one of the per-datagram outcomes
// (a short message delivered, a fragment kept, a channel nobody subscribes
// to, or one drop reason), so they add up to `datagrams`; the fuzz target
// checks that. The per-message counters say what became of reassemblies.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace plc::hmi {

struct TransportCounters {
  // per datagram
  std::uint64_t datagrams = 0;     // received from the socket
  std::uint64_t short_ok = 0;      // an LC02 message on a subscribed channel
  std::uint64_t fragment_ok = 0;   // an LC03 fragment kept for its message
  std::uint64_t unsubscribed = 0;  // a message (or its fragment 0) nobody subscribes to: ignored
  std::uint64_t bad_magic = 0;     // neither LC02 nor LC03
  std::uint64_t truncated = 0;     // shorter than its header, or cut by the socket
  std::uint64_t channel_unterminated = 0;  // no NUL after the channel within the datagram
  std::uint64_t channel_too_long = 0;      // more than 63 characters
  std::uint64_t oversized = 0;             // msg_size above the configured maximum
  // n_fragments 0, fragment_no >= n_fragments, or a piece outside msg_size
  // (fragment_offset + size computed without wrapping: the liblcm crash)
  std::uint64_t bad_fragment = 0;
  std::uint64_t duplicate_fragment = 0;  // a fragment number already received for that message
  std::uint64_t orphan_fragment = 0;  // no reassembly of its message (fragment 0 missed or dropped)
  // per message
  std::uint64_t messages = 0;               // complete messages handed to the subscribers
  std::uint64_t overlapping_fragments = 0;  // a complete set whose pieces do not tile the message
  std::uint64_t reassembly_abandoned = 0;   // its sender started another message first
  std::uint64_t reassembly_evicted = 0;     // stale, or made room (senders, bytes)
  // transport
  std::uint64_t recv_errors = 0;
  std::uint64_t send_errors = 0;
  std::uint64_t too_large_to_send = 0;   // a publish above the maximum message size
  std::uint64_t queue_full = 0;          // memq:// only: published while 10000 wait
  std::uint64_t handler_exceptions = 0;  // a subscriber threw; the next message is served

  // The datagrams that ended in a drop reason.
  [[nodiscard]] std::uint64_t dropped() const {
    return bad_magic + truncated + channel_unterminated + channel_too_long + oversized +
           bad_fragment + duplicate_fragment + orphan_fragment;
  }
  // Every counter by name (stats_t, plcctl stats), in the order above.
  [[nodiscard]] std::vector<std::pair<const char*, std::uint64_t>> named() const {
    return {{"datagrams", datagrams},
            {"short_ok", short_ok},
            {"fragment_ok", fragment_ok},
            {"unsubscribed", unsubscribed},
            {"bad_magic", bad_magic},
            {"truncated", truncated},
            {"channel_unterminated", channel_unterminated},
            {"channel_too_long", channel_too_long},
            {"oversized", oversized},
            {"bad_fragment", bad_fragment},
            {"duplicate_fragment", duplicate_fragment},
            {"orphan_fragment", orphan_fragment},
            {"messages", messages},
            {"overlapping_fragments", overlapping_fragments},
            {"reassembly_abandoned", reassembly_abandoned},
            {"reassembly_evicted", reassembly_evicted},
            {"recv_errors", recv_errors},
            {"send_errors", send_errors},
            {"too_large_to_send", too_large_to_send},
            {"queue_full", queue_full},
            {"handler_exceptions", handler_exceptions}};
  }
};

}  // namespace plc::hmi
