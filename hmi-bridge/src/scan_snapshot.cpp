#include "plc/hmi/scan_snapshot.hpp"

#include <new>

namespace plc::hmi {

ScanSnapshot::ScanSnapshot(int task, std::vector<Item> items)
    : task_(task), items_(std::move(items)) {
  std::size_t size = 0;
  for (Item& it : items_) {
    size = (size + 7) / 8 * 8;
    it.offset = size;
    size += it.var.type == VarType::STRING ? sizeof(STRING) : 8;
  }
  buf_.assign(size + 8, 0);
  for (const Item& it : items_)
    if (it.var.type == VarType::STRING) new (buf_.data() + it.offset) STRING();
}

void ScanSnapshot::on_scan_end(const TaskRuntime& t, const ScanContext& ctx) {
  if (state_.load(std::memory_order_acquire) != kRequested) return;
  for (const Item& it : items_) VarRegistry::read(it.var, buf_.data() + it.offset);
  (void)t;
  scan_ = ctx.cycle + 1;
  time_ = ctx.now;
  state_.store(kFilled, std::memory_order_release);
}

}  // namespace plc::hmi
