// A bounded single-producer, single-consumer queue of fixed-size records in
// shared memory: the HMI bridge's commands to plcrun and plcrun's replies.
// Positions only grow (64 bits never wrap); record k lives in slot
// k % capacity. The producer writes a record, then publishes its position
// (release); the consumer copies it out, then publishes its own.
//
// Either side may be the other process, and a crashed or hostile one may
// write anything into the positions it owns. Neither side trusts the
// other's position: a head more than `capacity` ahead of the tail (or
// behind it) is not plausible, and the consumer then skips to it (counted
// by the caller) instead of reading garbage slots; the producer treats an
// implausible tail as a full ring. A record is copied out before anything
// looks at it, so the other side cannot change it under the check.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace plc::hmi::ipc {

template <class Record>
class Ring {
  static_assert(std::is_trivially_copyable_v<Record>);

 public:
  Ring() = default;
  Ring(std::atomic<std::uint64_t>* head, std::atomic<std::uint64_t>* tail, Record* records,
       std::uint32_t capacity)
      : head_(head), tail_(tail), records_(records), capacity_(capacity) {}

  // The producer. False when the ring is full (nothing written).
  bool push(const Record& r) {
    const std::uint64_t h = head_->load(std::memory_order_relaxed);
    const std::uint64_t t = tail_->load(std::memory_order_acquire);
    if (t > h || h - t >= capacity_) return false;  // full, or a tail that is not plausible
    std::memcpy(static_cast<void*>(&records_[h % capacity_]), &r, sizeof r);
    head_->store(h + 1, std::memory_order_release);
    return true;
  }

  enum class Pop { Empty, Got, Skipped };
  // The consumer. Skipped: the producer's position was not plausible; the
  // ring is now empty (every record in it dropped).
  Pop pop(Record& out) {
    const std::uint64_t t = tail_->load(std::memory_order_relaxed);
    const std::uint64_t h = head_->load(std::memory_order_acquire);
    if (h == t) return Pop::Empty;
    if (h < t || h - t > capacity_) {
      tail_->store(h, std::memory_order_release);
      return Pop::Skipped;
    }
    std::memcpy(static_cast<void*>(&out), &records_[t % capacity_], sizeof out);
    tail_->store(t + 1, std::memory_order_release);
    return Pop::Got;
  }

  // Records waiting (the consumer's view; capacity + 1 when not plausible).
  [[nodiscard]] std::uint64_t waiting() const {
    const std::uint64_t h = head_->load(std::memory_order_acquire);
    const std::uint64_t t = tail_->load(std::memory_order_relaxed);
    return h < t || h - t > capacity_ ? capacity_ + 1 : h - t;
  }
  [[nodiscard]] std::uint32_t capacity() const { return capacity_; }

 private:
  std::atomic<std::uint64_t>* head_ = nullptr;
  std::atomic<std::uint64_t>* tail_ = nullptr;
  Record* records_ = nullptr;
  std::uint32_t capacity_ = 0;
};

}  // namespace plc::hmi::ipc
