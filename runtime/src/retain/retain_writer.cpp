#include "plc/retain/retain_writer.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "plc/retain/retain_file.hpp"
#include "plc/thread_guard.hpp"

namespace plc::retain {

Writer::Writer(Storage& storage) : storage_(storage) {}

Writer::~Writer() {
  if (thread_.joinable()) {
    state_.fetch_or(kStop, std::memory_order_release);
    state_.notify_all();
    thread_.join();
  }
}

void Writer::start(std::uint64_t next_sequence) {
  next_sequence_ = next_sequence;
  thread_ = std::thread([this] {
    // A failed writer saves nothing more until the stop: counted as a
    // failed save, its reason the last error, so that the stop (which
    // writes the final copy itself) says the file FAILED if that fails too,
    // and the run's exit code is 1 (thread_failures()).
    run_guarded(
        "retain writer", [this] { run(); },
        [this](std::string_view what) {
          {
            std::lock_guard<std::mutex> lock(mu_);
            ++failed_;
            last_error_ = "the writer thread failed: " + std::string(what);
          }
          dead_.store(true, std::memory_order_release);
        });
  });
}

bool Writer::offer(Slot& slot, std::span<const std::uint8_t> snapshot) {
  if ((state_.load(std::memory_order_acquire) & (kFull | kStop)) ||
      dead_.load(std::memory_order_acquire)) {
    skipped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  std::memcpy(slot.bytes.data(), snapshot.data(), slot.bytes.size());
  pending_.store(&slot, std::memory_order_relaxed);
  state_.fetch_or(kFull, std::memory_order_release);
  state_.notify_one();
  offered_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

void Writer::run() {
  for (;;) {
    std::uint32_t s = state_.load(std::memory_order_acquire);
    while (!(s & (kFull | kStop))) {
      state_.wait(s, std::memory_order_acquire);
      s = state_.load(std::memory_order_acquire);
    }
    if (!(s & kFull)) return;  // stopping, nothing pending
    if (before_write_) before_write_();
    const Slot& slot = *pending_.load(std::memory_order_relaxed);
    write_one(*slot.layout, slot.bytes);
    state_.fetch_and(~kFull, std::memory_order_release);
  }
}

std::string Writer::write_one(const Layout& layout, std::span<const std::uint8_t> snapshot) {
  // Unchanged only in the same file layout: after an online change the new
  // layout is written at once, even with the same values.
  if (have_last_ && last_hash_ == layout.hash() && last_.size() == snapshot.size() &&
      std::memcmp(last_.data(), snapshot.data(), last_.size()) == 0) {
    std::lock_guard<std::mutex> lock(mu_);
    ++unchanged_;
    return {};
  }
  std::uint64_t seq;
  {
    std::lock_guard<std::mutex> lock(mu_);
    seq = next_sequence_;
  }
  const std::int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::system_clock::now().time_since_epoch())
                               .count();
  encode(layout, snapshot, seq, now, encoded_);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string err = storage_.write(encoded_, seq);
  const std::int64_t took = (std::chrono::steady_clock::now() - t0).count();
  const std::int64_t lead = write_lead_ns_.load(std::memory_order_relaxed);
  write_lead_ns_.store(std::max(took, lead - lead / 8), std::memory_order_relaxed);
  std::lock_guard<std::mutex> lock(mu_);
  if (err.empty()) {
    last_.assign(snapshot.begin(), snapshot.end());  // the writer's thread: may allocate
    last_hash_ = layout.hash();
    have_last_ = true;
    ++written_;
    sequence_ = seq;
    ++next_sequence_;
    if (!last_error_.empty())
      std::fprintf(stderr, "plcrun: retain: saving works again (sequence %llu)\n",
                   static_cast<unsigned long long>(seq));
    last_error_.clear();
  } else {
    ++failed_;
    // Said once per new reason, not once per period of a full disk.
    if (err != last_error_)
      std::fprintf(stderr, "plcrun: retain: cannot save (the previous copy stays valid): %s\n",
                   err.c_str());
    last_error_ = err;
  }
  return err;
}

std::string Writer::stop(const Layout& layout, std::span<const std::uint8_t> final_snapshot) {
  if (thread_.joinable()) {
    state_.fetch_or(kStop, std::memory_order_release);
    state_.notify_all();
    thread_.join();
  }
  const std::string err = write_one(layout, final_snapshot);
  if (!err.empty() || !dead_.load(std::memory_order_acquire)) return err;
  // The final copy is saved, but the saves of the run stopped when the
  // thread failed: reported as a failure all the same.
  return "the writer thread failed during the run (the final copy was saved)";
}

WriterStats Writer::stats() const {
  WriterStats s;
  s.offered = offered_.load(std::memory_order_relaxed);
  s.skipped = skipped_.load(std::memory_order_relaxed);
  std::lock_guard<std::mutex> lock(mu_);
  s.written = written_;
  s.unchanged = unchanged_;
  s.failed = failed_;
  s.sequence = sequence_;
  s.last_error = last_error_;
  return s;
}

}  // namespace plc::retain
