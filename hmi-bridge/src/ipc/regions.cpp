#include "plc/hmi/ipc/regions.hpp"

#include <unistd.h>

#include <cstring>
#include <new>

namespace plc::hmi::ipc {

namespace {

// Where each part of the state region goes for `layout` (its slots placed
// from `slots_at`).
struct StatePlan {
  Section settings, layout, slots, stats, diag, outages, replies;
  std::size_t total = 0;
};

StatePlan plan_state(CellLayout& layout) {
  StatePlan p;
  std::size_t at = align_up(sizeof(StateHeader));
  auto take = [&at](std::size_t n) {
    const Section s{at, align_up(n)};
    at += s.size;
    return s;
  };
  p.settings = take(sizeof(Settings));
  // The layout's encoded size does not depend on the slots' offsets.
  p.layout = take(layout.encode().size());
  const std::size_t slots_at = at;
  for (CellLayout::Slot& s : layout.slots) {
    s.header = at;
    at += align_up(sizeof(SlotHeader));
    s.buffer = at;
    at += align_up(s.buffer_size);
  }
  p.slots = {slots_at, at - slots_at};
  p.stats = take(SeqBlock::kHeader + 64 + kStatsPerTask * layout.tasks.size());
  p.diag = take(SeqBlock::kHeader + 64 + kDiagPerDevice * layout.devices.size());
  p.outages = take(SeqBlock::kHeader + 64 + OutageNote::kKept * (40 + 256));
  p.replies = take(sizeof(ReplyRecord) * kReplyCapacity);
  p.total = at;
  return p;
}

std::size_t control_size() {
  return align_up(sizeof(ControlHeader)) + align_up(sizeof(CommandRecord) * kCommandCapacity);
}

bool inside(const Section& s, std::size_t size) {
  return s.offset <= size && s.size <= size - s.offset && s.offset % 8 == 0;
}

}  // namespace

std::unique_ptr<Regions> Regions::create(const Settings& settings, CellLayout& layout,
                                         std::uint64_t boot_epoch) {
  const StatePlan p = plan_state(layout);
  std::unique_ptr<Regions> r(new Regions);
  r->state_map_ = Mapping::create("plc-hmi-state", p.total);
  r->control_map_ = Mapping::create("plc-hmi-control", control_size());
  r->state_ = r->state_map_.data();
  r->control_ = r->control_map_.data();
  r->state_size_ = p.total;
  r->control_size_ = control_size();

  auto* st = new (r->state_) StateHeader();
  st->size = p.total;
  st->boot_epoch = boot_epoch;
  st->host_pid = std::uint64_t(::getpid());
  st->settings = p.settings;
  st->layout = p.layout;
  st->slots = p.slots;
  st->stats = p.stats;
  st->diag = p.diag;
  st->outages = p.outages;
  st->replies = p.replies;
  st->slot_count = std::uint32_t(layout.slots.size());
  new (r->state_ + p.settings.offset) Settings(settings);
  for (const CellLayout::Slot& s : layout.slots) new (r->state_ + s.header) SlotHeader();
  for (const Section& b : {p.stats, p.diag, p.outages}) new (r->state_ + b.offset) SeqHeader();

  auto* ct = new (r->control_) ControlHeader();
  ct->size = r->control_size_;
  ct->commands = {align_up(sizeof(ControlHeader)),
                  align_up(sizeof(CommandRecord) * kCommandCapacity)};
  r->write_layout(layout);
  st->generation.store(2, std::memory_order_release);
  r->state_map_.seal_future_writes();
  return r;
}

std::unique_ptr<Regions> Regions::attach(int state_fd, int control_fd, std::string& error) {
  std::unique_ptr<Regions> r(new Regions);
  r->state_map_ = Mapping::attach(state_fd, false, error);
  if (!r->state_map_) return nullptr;
  r->control_map_ = Mapping::attach(control_fd, true, error);
  if (!r->control_map_) return nullptr;
  r->state_ = r->state_map_.data();
  r->control_ = r->control_map_.data();
  r->state_size_ = r->state_map_.size();
  r->control_size_ = r->control_map_.size();
  if (!r->check(error)) return nullptr;
  return r;
}

std::unique_ptr<Regions> Regions::view() const {
  std::unique_ptr<Regions> r(new Regions);
  r->state_ = state_;
  r->control_ = control_;
  r->state_size_ = state_size_;
  r->control_size_ = control_size_;
  return r;
}

bool Regions::check(std::string& error) const {
  if (state_size_ < sizeof(StateHeader) || control_size_ < sizeof(ControlHeader)) {
    error = "shared memory too small for its header";
    return false;
  }
  const StateHeader& s = state();
  const ControlHeader& c = control();
  if (s.magic != kStateMagic || c.magic != kControlMagic || s.version != kVersion ||
      c.version != kVersion) {
    error = "shared memory of another kind or version (plcrun and plchmi from different builds?)";
    return false;
  }
  const bool ok =
      s.size == state_size_ && c.size == control_size_ && inside(s.settings, state_size_) &&
      s.settings.size >= sizeof(Settings) && inside(s.layout, state_size_) &&
      inside(s.slots, state_size_) && inside(s.stats, state_size_) &&
      s.stats.size > SeqBlock::kHeader && inside(s.diag, state_size_) &&
      s.diag.size > SeqBlock::kHeader && inside(s.outages, state_size_) &&
      s.outages.size > SeqBlock::kHeader && inside(s.replies, state_size_) &&
      s.reply_capacity > 0 && s.replies.size >= sizeof(ReplyRecord) * s.reply_capacity &&
      s.slot_count <= kMaxSlots && inside(c.commands, control_size_) && c.command_capacity > 0 &&
      c.commands.size >= sizeof(CommandRecord) * c.command_capacity;
  if (!ok) error = "shared memory whose sections do not fit it";
  return ok;
}

Ring<CommandRecord> Regions::commands() const {
  ControlHeader& c = control();
  return Ring<CommandRecord>(&c.command_head, &state().command_tail,
                             reinterpret_cast<CommandRecord*>(control_ + c.commands.offset),
                             c.command_capacity);
}

Ring<ReplyRecord> Regions::replies() const {
  StateHeader& s = state();
  return Ring<ReplyRecord>(&s.reply_head, &control().reply_tail,
                           reinterpret_cast<ReplyRecord*>(state_ + s.replies.offset),
                           s.reply_capacity);
}

bool Regions::fits(CellLayout& layout) const {
  const StatePlan p = plan_state(layout);
  const StateHeader& s = state();
  return p.total == state_size_ && p.layout.size == s.layout.size &&
         p.slots.offset == s.slots.offset && p.slots.size == s.slots.size &&
         p.stats.size == s.stats.size && p.diag.size == s.diag.size &&
         layout.slots.size() == s.slot_count;
}

void Regions::write_layout(const CellLayout& layout) {
  StateHeader& s = state();
  const std::vector<unsigned char> bytes = layout.encode();
  // Byte by byte as atomics: the bridge may be copying it out meanwhile
  // (it then sees the generation change and throws its copy away).
  for (std::size_t i = 0; i < bytes.size(); ++i)
    std::atomic_ref<unsigned char>(state_[s.layout.offset + i])
        .store(bytes[i], std::memory_order_relaxed);
  s.layout_size.store(bytes.size(), std::memory_order_relaxed);
  // Every task's first scan copies its values (the bridge's first round
  // then has them).
  for (std::size_t k = 0; k < layout.slots.size(); ++k) {
    const std::uint64_t filled =
        slot_header(layout.slots[k]).filled.load(std::memory_order_relaxed);
    control().requests[k].store(filled + 1, std::memory_order_relaxed);
  }
}

void Regions::rewrite(const CellLayout& layout) {
  StateHeader& s = state();
  const std::uint64_t g = s.generation.load(std::memory_order_relaxed);
  s.generation.store(g + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  write_layout(layout);
  s.generation.store(g + 2, std::memory_order_release);
}

std::optional<CellLayout> Regions::read_layout(std::uint64_t& generation,
                                               std::string& error) const {
  const StateHeader& s = state();
  const std::uint64_t g1 = s.generation.load(std::memory_order_acquire);
  if (g1 & 1) {
    error = "plcrun is rewriting the cell layout";
    return std::nullopt;
  }
  const std::uint64_t n = s.layout_size.load(std::memory_order_relaxed);
  if (n > s.layout.size) {
    error = "cell layout larger than its section";
    return std::nullopt;
  }
  // A private copy: plcrun may start a rewrite while this decodes.
  std::vector<unsigned char> copy(n);
  for (std::size_t i = 0; i < n; ++i)
    copy[i] =
        std::atomic_ref<unsigned char>(state_[s.layout.offset + i]).load(std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_acquire);
  if (s.generation.load(std::memory_order_relaxed) != g1) {
    error = "plcrun rewrote the cell layout meanwhile";
    return std::nullopt;
  }
  auto l = CellLayout::decode(copy.data(), copy.size(), state_size_, error);
  if (l) generation = g1;
  return l;
}

}  // namespace plc::hmi::ipc
