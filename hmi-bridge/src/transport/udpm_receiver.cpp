#include "plc/hmi/udpm_receiver.hpp"

#include <algorithm>
#include <cstring>
#include <new>

#include "plc/hmi/udpm_wire.hpp"

namespace plc::hmi {

namespace {

// The bookkeeping of a reassembly besides its data, charged up front.
std::size_t bookkeeping(std::uint16_t n_fragments) {
  return (std::size_t(n_fragments) + 63) / 64 * 8 + std::size_t(n_fragments) * 8;
}

}  // namespace

UdpmReceiver::UdpmReceiver(const UdpmLimits& limits, Wanted wanted)
    : limits_(limits), wanted_(std::move(wanted)) {
  // Room for one message of the largest size, or nothing could ever be
  // reassembled.
  limits_.max_senders = std::max<std::size_t>(limits_.max_senders, 1);
  limits_.max_reassembly_bytes =
      std::max(limits_.max_reassembly_bytes,
               limits_.max_message_bytes + bookkeeping(std::uint16_t(udpm::kMaxFragments)));
  open_.reserve(limits_.max_senders);
  done_channel_.reserve(udpm::kMaxChannelLength + 1);
}

std::optional<UdpmMessage> UdpmReceiver::take(std::span<const std::uint8_t> d, std::uint64_t sender,
                                              std::int64_t now_us,
                                              std::int64_t recv_utime) noexcept {
  ++counters_.datagrams;
  if (d.size() < 4) {
    ++counters_.truncated;
    return std::nullopt;
  }
  const std::uint32_t magic = udpm::get_u32(d.data());
  if (magic == udpm::kMagicShort) return take_short(d, recv_utime);
  if (magic == udpm::kMagicFragment) return take_fragment(d, sender, now_us, recv_utime);
  ++counters_.bad_magic;
  return std::nullopt;
}

int UdpmReceiver::channel_length(std::span<const std::uint8_t> body) {
  // liblcm takes strlen() here, reading past a datagram without a NUL.
  const std::size_t look = std::min(body.size(), udpm::kMaxChannelLength + 1);
  const void* nul = std::memchr(body.data(), 0, look);
  if (nul) return int(static_cast<const std::uint8_t*>(nul) - body.data());
  if (body.size() > udpm::kMaxChannelLength)
    ++counters_.channel_too_long;
  else
    ++counters_.channel_unterminated;
  return -1;
}

std::optional<UdpmMessage> UdpmReceiver::take_short(std::span<const std::uint8_t> d,
                                                    std::int64_t recv_utime) {
  if (d.size() < udpm::kShortHeaderSize) {
    ++counters_.truncated;
    return std::nullopt;
  }
  const auto body = d.subspan(udpm::kShortHeaderSize);
  const int len = channel_length(body);
  if (len < 0) return std::nullopt;
  const auto payload = body.subspan(std::size_t(len) + 1);
  if (payload.size() > limits_.max_message_bytes) {
    ++counters_.oversized;
    return std::nullopt;
  }
  const std::string_view channel(reinterpret_cast<const char*>(body.data()), std::size_t(len));
  if (!wanted_(channel)) {
    ++counters_.unsubscribed;
    return std::nullopt;
  }
  ++counters_.short_ok;
  ++counters_.messages;
  return UdpmMessage{channel, payload, recv_utime};
}

std::optional<UdpmMessage> UdpmReceiver::take_fragment(std::span<const std::uint8_t> d,
                                                       std::uint64_t sender, std::int64_t now_us,
                                                       std::int64_t recv_utime) {
  if (d.size() < udpm::kFragmentHeaderSize) {
    ++counters_.truncated;
    return std::nullopt;
  }
  const std::uint32_t seqno = udpm::get_u32(d.data() + 4);
  const std::uint32_t msg_size = udpm::get_u32(d.data() + 8);
  const std::uint32_t offset = udpm::get_u32(d.data() + 12);
  const std::uint16_t no = udpm::get_u16(d.data() + 16);
  const std::uint16_t n = udpm::get_u16(d.data() + 18);
  if (n == 0 || no >= n) {
    ++counters_.bad_fragment;
    return std::nullopt;
  }
  if (msg_size > limits_.max_message_bytes) {
    ++counters_.oversized;
    return std::nullopt;
  }
  auto body = d.subspan(udpm::kFragmentHeaderSize);
  std::string_view channel;
  if (no == 0) {
    const int len = channel_length(body);
    if (len < 0) return std::nullopt;
    channel = {reinterpret_cast<const char*>(body.data()), std::size_t(len)};
    body = body.subspan(std::size_t(len) + 1);
  }
  // Both sides within msg_size, compared without a sum that could wrap.
  if (offset > msg_size || body.size() > msg_size - offset) {
    ++counters_.bad_fragment;
    return std::nullopt;
  }

  Reassembly* r = nullptr;
  for (std::size_t i = 0; i < open_.size(); ++i) {
    if (open_[i].sender != sender) continue;
    Reassembly& o = open_[i];
    if (now_us - o.last_us > limits_.reassembly_timeout_us) {
      ++counters_.reassembly_evicted;
      remove(i);
    } else if (o.seqno != seqno || o.msg_size != msg_size || o.n_fragments != n) {
      ++counters_.reassembly_abandoned;
      remove(i);
    } else {
      r = &o;
    }
    break;
  }
  if (!r) {
    if (no != 0) {
      ++counters_.orphan_fragment;
      return std::nullopt;
    }
    if (!wanted_(channel)) {
      ++counters_.unsubscribed;
      return std::nullopt;
    }
    r = start(sender, seqno, msg_size, n, channel, now_us);
    if (!r) return std::nullopt;
  }
  std::uint64_t& word = r->seen[no / 64];
  const std::uint64_t bit = std::uint64_t(1) << (no % 64);
  if (word & bit) {
    ++counters_.duplicate_fragment;
    return std::nullopt;
  }
  word |= bit;
  if (!body.empty()) std::memcpy(r->data.data() + offset, body.data(), body.size());
  r->pieces.push_back({offset, std::uint32_t(body.size())});  // reserved: never allocates
  ++r->received;
  r->last_us = now_us;
  ++counters_.fragment_ok;
  if (r->received < r->n_fragments) return std::nullopt;

  // Every fragment number arrived once: the pieces must cover the message
  // exactly, else part of it would be zeros the sender never sent.
  std::sort(r->pieces.begin(), r->pieces.end(),
            [](const Piece& a, const Piece& b) { return a.offset < b.offset; });
  std::uint64_t end = 0;
  bool tiles = true;
  for (const Piece& p : r->pieces) {
    if (p.size == 0) continue;
    tiles &= p.offset == end;
    end = std::uint64_t(p.offset) + p.size;
  }
  tiles &= end == r->msg_size;
  const std::size_t index = std::size_t(r - open_.data());
  if (!tiles) {
    ++counters_.overlapping_fragments;
    remove(index);
    return std::nullopt;
  }
  done_channel_.assign(r->channel);  // reserved: at most 63 characters
  done_data_ = std::move(r->data);
  remove(index);
  ++counters_.messages;
  return UdpmMessage{done_channel_, done_data_, recv_utime};
}

UdpmReceiver::Reassembly* UdpmReceiver::start(std::uint64_t sender, std::uint32_t seqno,
                                              std::uint32_t msg_size, std::uint16_t n_fragments,
                                              std::string_view channel, std::int64_t now_us) {
  const std::size_t cost = std::size_t(msg_size) + bookkeeping(n_fragments);
  // Stale ones first, then the least recently fed, until it fits.
  for (std::size_t i = open_.size(); i-- > 0;)
    if (now_us - open_[i].last_us > limits_.reassembly_timeout_us) {
      ++counters_.reassembly_evicted;
      remove(i);
    }
  while (!open_.empty() &&
         (open_.size() >= limits_.max_senders || bytes_ + cost > limits_.max_reassembly_bytes)) {
    std::size_t lru = 0;
    for (std::size_t i = 1; i < open_.size(); ++i)
      if (open_[i].last_us < open_[lru].last_us) lru = i;
    ++counters_.reassembly_evicted;
    remove(lru);
  }
  Reassembly r;
  try {
    r.channel.assign(channel);
    r.data.assign(msg_size, 0);
    r.seen.assign((std::size_t(n_fragments) + 63) / 64, 0);
    r.pieces.reserve(n_fragments);
  } catch (const std::bad_alloc&) {  // within the limits, yet no memory: as too large
    ++counters_.oversized;
    return nullptr;
  }
  r.sender = sender;
  r.seqno = seqno;
  r.msg_size = msg_size;
  r.n_fragments = n_fragments;
  r.last_us = now_us;
  r.cost = cost;
  bytes_ += cost;
  open_.push_back(std::move(r));  // reserved to max_senders: never allocates
  return &open_.back();
}

void UdpmReceiver::remove(std::size_t index) {
  bytes_ -= open_[index].cost;
  if (index + 1 != open_.size()) open_[index] = std::move(open_.back());
  open_.pop_back();
}

}  // namespace plc::hmi
