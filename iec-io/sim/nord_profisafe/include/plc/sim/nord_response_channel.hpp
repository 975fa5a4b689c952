// The device -> host path of the simulated NORD F-device, as a fieldbus
// carries cyclic frames: in order, each no sooner than its delay after the
// device sent it; the host sees the newest frame that has arrived, so a
// frame overtaken by a newer one before the host looked is simply skipped.
// A delay episode (fault injection, spec §8.4 item 3) sets the delay of the
// frames the device sends while it lasts; frames sent before or after keep
// theirs, and none overtakes another.
//
// Each frame carries a tag: when the device sent it, when the telegram in it
// was produced (earlier for a repeated telegram), the F-data the device meant
// and what was injected. Tests measure with it what the host handed over;
// the host never sees the tag.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "plc/types.hpp"

namespace plc::sim {

struct NordFrameTag {
  std::uint64_t id = 0;                // 1, 2, ... per frame the device sent
  TIME sent{};                         // when the device sent the frame
  TIME produced{};                     // when the telegram in it was produced
  std::array<std::uint8_t, 4> data{};  // that telegram's F-data, uncorrupted
  bool corrupted = false;              // a bit was flipped on the way
  bool foreign = false;                // CRC2 seeded with another CRC1 (masquerade)
  bool repeated = false;               // an older telegram sent again
};

class NordResponseChannel {
 public:
  static constexpr std::size_t kPdu = 8;
  static constexpr std::size_t kFrames = 64;
  using Pdu = std::array<std::uint8_t, kPdu>;

  // Frames the device sends from the next send() on, for `how_long`, are
  // delayed by `d` (at least; order is kept).
  void delay(TIME d, TIME how_long) {
    delay_ = d;
    delay_for_ = how_long;
    delay_pending_ = true;
    refresh_direct();
  }

  struct Frame {
    TIME arrive{};
    Pdu pdu{};
    NordFrameTag tag{};
  };

  void send(TIME now, const Pdu& pdu, const NordFrameTag& tag) {
    Frame& f = push(now);
    f.pdu = pdu;
    f.tag = tag;
  }
  // send() that leaves the PDU and the tag to the caller: it writes them
  // into the frame returned (every field; no copy through a temporary),
  // before it uses the channel again.
  Frame& push(TIME now) {
    if (delay_pending_) {
      delay_until_ = now + delay_for_;
      delay_pending_ = false;
    }
    const TIME d = now < delay_until_ ? delay_ : TIME{};
    const TIME arrive = now + d > last_arrival_ ? now + d : last_arrival_;
    last_arrival_ = arrive;
    if (count_ == kFrames) pop();  // full: the oldest in flight is lost
    Frame& f = ring_[(first_ + count_) % kFrames];
    f.arrive = arrive;
    ++count_;
    refresh_direct();
    return f;
  }

  // push() for a frame that deliver(now) follows with nothing between: with
  // no frame in flight and no delay in force the frame arrives at once and
  // deliver() would show it, so it is written where the shown one lives
  // (no ring slot, no copy at delivery). Else push().
  Frame& push_delivered(TIME now) {
    // count_ == 0 && !delay_pending_ && now >= delay_until_ &&
    // last_arrival_ <= now, as one compare (direct_from_).
    // direct_from_ = max(delay_until_, last_arrival_) = now, delay_until_ <= now.
    if (direct(now)) return push_direct(now);
    return push(now);
  }

  // push_delivered()'s condition, and its frame when it holds (the caller
  // asked direct(now) first).
  [[nodiscard]] bool direct(TIME now) const { return now >= direct_from_; }
  Frame& push_direct(TIME now) {
    last_arrival_ = now;
    direct_from_ = now;
    shown_.arrive = now;
    return shown_;
  }

  // Everything that has arrived by `now`; the newest becomes the one shown.
  void deliver(TIME now) {
    if (count_ == 0) return;  // nothing in flight (the usual step)
    while (count_ > 0 && ring_[first_].arrive <= now) {
      shown_ = ring_[first_];
      pop();
    }
    refresh_direct();
  }

  [[nodiscard]] const Pdu& shown() const { return shown_.pdu; }
  [[nodiscard]] const NordFrameTag& shown_tag() const { return shown_.tag; }
  [[nodiscard]] std::size_t in_flight() const { return count_; }

 private:
  void pop() {
    first_ = (first_ + 1) % kFrames;
    --count_;
  }
  // push_delivered()'s condition as the earliest time it holds, kept at
  // each change of what it is made of (count_, delay_pending_,
  // delay_until_, last_arrival_: push(), delay(), deliver(), and
  // push_delivered() itself): never while a frame is in flight or a delay
  // waits to start, else from the later of the delay's end and the last
  // arrival.
  void refresh_direct() {
    direct_from_ =
        count_ != 0 || delay_pending_ ? TIME::max() : std::max(delay_until_, last_arrival_);
  }

  // The device sends a frame only when it answers a new request and the host
  // sends a request only after an answer, so a handful are ever in flight.
  std::array<Frame, kFrames> ring_{};
  std::size_t first_ = 0, count_ = 0;
  Frame shown_{};
  TIME last_arrival_{}, delay_{}, delay_for_{}, delay_until_{};
  bool delay_pending_ = false;
  TIME direct_from_{};  // refresh_direct(); nothing in flight, no delay at first
};

}  // namespace plc::sim
