// Fuzz target: our LCM udpm receiver (plc/hmi/udpm_receiver.hpp, issue 22),
// the parser that replaced liblcm's in the bridge and plcctl. The first
// byte picks the part:
//  0 datagrams from several senders into one receiver with small limits
//    (256 KiB messages, 4 senders, 800 KiB of reassembly): each record is
//    [sender][time step][length, u16 little-endian][bytes]. Properties:
//    every datagram is counted once (the outcomes add up to `datagrams`);
//    reassemblies and their bytes stay within the limits; a message handed
//    out is at most the maximum size, on a channel of at most 63 bytes
//    without a NUL;
//  1 a valid message (channel and size from the input, bytes from a
//    seeded generator) encoded by our encoder, its fragments fed in an
//    order the input picks (fragment 0 first), some twice, with datagrams
//    of input bytes from three other senders between (room for all four:
//    nothing evicts it). Property: it comes out once, byte for byte, at
//    its last fragment, and nothing else comes out of its sender.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "plc/hmi/udpm_receiver.hpp"
#include "plc/hmi/udpm_wire.hpp"

using plc::fuzz::FuzzInput;
using namespace plc::hmi;

namespace {

UdpmLimits small_limits() {
  UdpmLimits l;
  l.max_message_bytes = 256 * 1024;
  l.max_senders = 4;
  l.max_reassembly_bytes = 800 * 1024;
  l.reassembly_timeout_us = 1000;
  return l;
}

void check(const UdpmReceiver& r) {
  const TransportCounters& c = r.counters();
  if (c.datagrams != c.short_ok + c.fragment_ok + c.unsubscribed + c.dropped()) __builtin_trap();
  if (r.reassemblies() > r.limits().max_senders) __builtin_trap();
  if (r.reassembly_bytes() > r.limits().max_reassembly_bytes) __builtin_trap();
}

void check(const UdpmMessage& m, const UdpmReceiver& r) {
  if (m.data.size() > r.limits().max_message_bytes) __builtin_trap();
  if (m.channel.size() > udpm::kMaxChannelLength) __builtin_trap();
  if (m.channel.find('\0') != std::string_view::npos) __builtin_trap();
}

void datagrams(FuzzInput& in) {
  UdpmReceiver r(small_limits(), [](std::string_view c) { return c.empty() || c[0] != 'X'; });
  std::int64_t now = 0;
  for (int i = 0; i < 256 && !in.empty(); ++i) {
    const std::uint64_t sender = in.byte() % 6;
    now += in.byte();
    const std::size_t len = in.integral<std::uint16_t>();
    const auto d = in.bytes(len);
    if (const auto m = r.take(d, sender, now, now)) check(*m, r);
    check(r);
  }
}

void round_trip(FuzzInput& in) {
  std::string channel;
  for (std::size_t n = in.byte() % 64, k = 0; k < n; ++k) channel += char('A' + in.byte() % 26);
  const std::size_t size = std::min<std::size_t>(in.integral<std::uint16_t>() * 4U, 250000);
  std::vector<std::uint8_t> payload(size);
  std::uint32_t x = in.integral<std::uint32_t>() | 1;
  for (auto& b : payload) {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    b = std::uint8_t(x);
  }
  std::vector<std::vector<std::uint8_t>> frags;
  udpm::for_each_datagram(
      channel, payload, in.integral<std::uint32_t>(), [&](const udpm::Datagram& d) {
        std::vector<std::uint8_t> b(d.head.begin(), d.head.begin() + long(d.head_size));
        b.insert(b.end(), d.body.begin(), d.body.end());
        frags.push_back(std::move(b));
        return true;
      });
  if (frags.empty()) __builtin_trap();  // a channel of at most 63, a size under 4 GiB
  // The order: fragment 0, then the others as the input shuffles them.
  std::vector<std::size_t> order(frags.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  for (std::size_t k = order.size(); k > 2; --k)
    std::swap(order[k - 1], order[1 + in.byte() % (k - 1)]);
  // Room for four messages of the largest size: the other senders' claims
  // never evict sender 1's message.
  UdpmLimits room = small_limits();
  room.max_reassembly_bytes = 4 << 20;
  UdpmReceiver r(room, [](std::string_view) { return true; });
  int delivered = 0;
  std::int64_t now = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    for (int extra = in.byte() % 3; extra > 0; --extra) {  // another sender's datagram
      const auto junk = in.bytes(in.byte());
      if (const auto m = r.take(junk, 2 + in.byte() % 3, now, now)) check(*m, r);
    }
    const auto& d = frags[order[k]];
    // A fragment twice (a short message twice is two messages, as in liblcm).
    for (int copies = 1 + (frags.size() > 1 && in.byte() == 0xFF); copies > 0; --copies) {
      const auto m = r.take(d, 1, now, now);
      check(r);
      if (!m) continue;
      if (k + 1 != order.size() || m->channel != channel ||
          !std::equal(m->data.begin(), m->data.end(), payload.begin(), payload.end()))
        __builtin_trap();
      ++delivered;
    }
  }
  if (delivered != 1) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  plc::fuzz::run_one_of(in, datagrams, round_trip);
  return 0;
}
