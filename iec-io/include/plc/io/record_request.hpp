// An asynchronous acyclic request (record read or write), as RDREC/WRREC.
//
// The FB owns the request object (no heap). It fills it, submits it through
// its DevicePort, and polls status() in later scans. The plugin completes it
// from its own context (a bus thread in real time, the lockstep step in
// virtual time) and publishes the result with a release store, so the FB
// sees either Queued or the complete answer, never a half-written one.
//
// Under a Runtime the link is "deferred": the plugin's answer is parked and
// becomes visible only when the submitting task latches its next scan
// (DeviceLink::deliver_answered). An answer therefore never appears in the
// middle of a scan, in real time as in virtual time, and a recording logs
// it in exactly the scan that first sees it.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

namespace plc::io {

// 240 bytes: the PROFIdrive parameter channel's maximum record (DPV1 data
// unit); enough for the PROFIsafe F-parameter block and DeviceNet explicit
// messages too.
inline constexpr std::size_t kRecordMaxBytes = 240;

enum class RecordKind : std::uint8_t { Read, Write };

enum class RecordStatus : std::uint8_t {
  Idle,    // not submitted (or collected)
  Queued,  // submitted, no answer yet
  Done,    // answered; for a read, data()[0..length) is valid
  Error,   // refused; error_code() tells why
};

// Error codes of a refused record request (plugin or device level). Values
// follow the PNIO error-decode idea of separating transport from device
// causes; device models may return their own codes >= 0x100.
enum class RecordError : std::uint16_t {
  None = 0,
  InvalidIndex = 1,   // the device has no such record
  InvalidLength = 2,  // write too long / read buffer too small
  DeviceBusy = 3,     // the device refuses for now; retry later
  NotReachable = 4,   // device offline or not answering
  QueueFull = 5,      // too many requests in flight on this device
  Timeout = 6,        // no answer within the plugin's record timeout
  InvalidState = 7,   // the device refuses in its present state
};

class RecordRequest {
 public:
  RecordRequest() = default;
  RecordRequest(const RecordRequest&) = delete;
  RecordRequest& operator=(const RecordRequest&) = delete;

  // Prepare a write of `data` to record `index` (copies, truncating to the
  // maximum size; returns false if it did not fit).
  bool prepare_write(std::uint16_t index, std::span<const std::uint8_t> data) {
    kind_ = RecordKind::Write;
    index_ = index;
    if (data.size() > kRecordMaxBytes) return false;
    std::memcpy(data_.data(), data.data(), data.size());
    length_ = static_cast<std::uint16_t>(data.size());
    return true;
  }
  void prepare_read(std::uint16_t index) {
    kind_ = RecordKind::Read;
    index_ = index;
    length_ = 0;
  }

  // A read that first sends request bytes (a DeviceNet explicit service names
  // class/instance/attribute in them: explicit_message.hpp). Until the plugin
  // answers, data() holds the request; the answer then replaces it. Returns
  // false (and prepares nothing) if the request does not fit.
  bool prepare_read(std::uint16_t index, std::span<const std::uint8_t> request) {
    if (request.size() > kRecordMaxBytes) return false;
    kind_ = RecordKind::Read;
    index_ = index;
    std::memcpy(data_.data(), request.data(), request.size());
    length_ = static_cast<std::uint16_t>(request.size());
    return true;
  }

  [[nodiscard]] RecordStatus status() const { return status_.load(std::memory_order_acquire); }
  [[nodiscard]] bool busy() const { return status() == RecordStatus::Queued; }
  [[nodiscard]] RecordKind kind() const { return kind_; }
  [[nodiscard]] std::uint16_t index() const { return index_; }
  [[nodiscard]] RecordError error() const { return error_; }
  [[nodiscard]] std::uint16_t error_code() const { return static_cast<std::uint16_t>(error_); }
  [[nodiscard]] std::span<const std::uint8_t> data() const { return {data_.data(), length_}; }
  // Marks a finished request as collected so the FB can reuse it.
  void reset() {
    if (status() != RecordStatus::Queued)
      status_.store(RecordStatus::Idle, std::memory_order_relaxed);
  }

  // ---- completion side (plugins) ----
  std::span<std::uint8_t> buffer() { return {data_.data(), data_.size()}; }
  void mark_queued() {
    error_ = RecordError::None;
    parked_.store(RecordStatus::Idle, std::memory_order_relaxed);
    status_.store(RecordStatus::Queued, std::memory_order_release);
  }
  void complete(std::size_t length) {
    length_ = static_cast<std::uint16_t>(length);
    error_ = RecordError::None;
    publish(RecordStatus::Done);
  }
  void fail(RecordError e, std::uint16_t device_code = 0) {
    error_ = device_code ? static_cast<RecordError>(device_code) : e;
    length_ = 0;
    publish(RecordStatus::Error);
  }
  // Replay: finish with exactly what a recording says the device answered.
  void finish_as(RecordStatus st, std::uint16_t error, std::span<const std::uint8_t> data) {
    const std::size_t n = data.size() < kRecordMaxBytes ? data.size() : kRecordMaxBytes;
    std::memcpy(data_.data(), data.data(), n);
    length_ = static_cast<std::uint16_t>(n);
    error_ = static_cast<RecordError>(error);
    status_.store(st, std::memory_order_release);
  }
  // Submission number on its device link (recording and replay match
  // answers to requests by it).
  [[nodiscard]] std::uint32_t seq() const { return seq_; }
  void set_seq(std::uint32_t s) { seq_ = s; }

  // ---- deferred delivery (DeviceLink) ----
  // Set at submission: park the answer until delivered, and which task
  // (Runtime task order; -1 = any) submitted it.
  void set_delivery(bool deferred, int owner) {
    deferred_ = deferred;
    owner_ = owner;
  }
  [[nodiscard]] int owner() const { return owner_; }
  [[nodiscard]] bool answer_parked() const {
    return parked_.load(std::memory_order_acquire) != RecordStatus::Idle;
  }
  // Makes a parked answer visible to the FB; false if there is none.
  bool deliver() {
    const RecordStatus st = parked_.load(std::memory_order_acquire);
    if (st == RecordStatus::Idle) return false;
    parked_.store(RecordStatus::Idle, std::memory_order_relaxed);
    status_.store(st, std::memory_order_release);
    return true;
  }

 private:
  void publish(RecordStatus st) {
    if (deferred_)
      parked_.store(st, std::memory_order_release);
    else
      status_.store(st, std::memory_order_release);
  }

  std::array<std::uint8_t, kRecordMaxBytes> data_{};
  std::atomic<RecordStatus> status_{RecordStatus::Idle};
  std::atomic<RecordStatus> parked_{RecordStatus::Idle};  // answered, not yet delivered
  bool deferred_ = false;
  int owner_ = -1;
  RecordKind kind_ = RecordKind::Read;
  RecordError error_ = RecordError::None;
  std::uint16_t index_ = 0;
  std::uint16_t length_ = 0;
  std::uint32_t seq_ = 0;
};

}  // namespace plc::io
