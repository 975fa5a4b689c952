#include "plc/hmi/scan_snapshot.hpp"

#include <cstring>
#include <ctime>
#include <new>

namespace plc::hmi {

ScanSnapshot::ScanSnapshot(int task, std::vector<Item> items)
    : task_(task), items_(std::move(items)) {
  std::size_t size = 0;
  for (std::size_t i = 0; i < items_.size(); ++i) {
    Item& it = items_[i];
    const bool plain = !it.var.address && it.var.type != VarType::STRING;
    if (!plain) {
      size = (size + 7) / 8 * 8;
      it.offset = size;
      size += it.var.type == VarType::STRING ? sizeof(STRING) : 8;
      one_by_one_.push_back(i);
      continue;
    }
    const auto* src = static_cast<const unsigned char*>(it.var.ptr);
    const std::size_t n = size_of(it.var.type);
    if (!runs_.empty() && runs_.back().src + runs_.back().len == src &&
        runs_.back().dst + runs_.back().len == size) {
      runs_.back().len += n;  // continues the run, in memory and in the buffer
    } else {
      size = (size + 7) / 8 * 8;
      runs_.push_back({src, size, n});
    }
    it.offset = size;
    size += n;
  }
  size_ = (size + 7) / 8 * 8 + 8;
}

void ScanSnapshot::bind(ipc::SlotHeader* header, unsigned char* buffer,
                        const std::atomic<std::uint64_t>* request) {
  header_ = header;
  buf_ = buffer;
  request_ = request;
  served_ = header->filled.load(std::memory_order_relaxed);
  for (const Item& it : items_)
    if (it.var.type == VarType::STRING) new (buf_ + it.offset) STRING();
}

void ScanSnapshot::on_scan_end(const TaskRuntime& t, const ScanContext& ctx) {
  // The bridge's word, whatever it wrote: a number not served yet means copy.
  const std::uint64_t asked = request_->load(std::memory_order_acquire);
  if (asked == served_) return;
  for (const Run& r : runs_) std::memcpy(buf_ + r.dst, r.src, r.len);
  for (std::size_t i : one_by_one_) VarRegistry::read(items_[i].var, buf_ + items_[i].offset);
  (void)t;
  header_->scan = ctx.cycle + 1;
  header_->plc_time_ns = ctx.now.count();
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);  // vDSO: no system call, no allocation
  header_->copy_utime = std::int64_t(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1000;
  header_->filled.store(asked, std::memory_order_release);
  served_ = asked;
}

}  // namespace plc::hmi
