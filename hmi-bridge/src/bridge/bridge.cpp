#include "plc/hmi/bridge.hpp"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "bridge_view.hpp"
#include "plc/hmi/checked_decode.hpp"
#include "plc/hmi/utime.hpp"
#include "plc/hmi/value_text.hpp"
#include "softplc_hmi/trace_sample_t.hpp"
#include "softplc_hmi/values_t.hpp"

namespace plc::hmi {

namespace {

std::string bounded(const char* s, std::size_t cap) { return std::string(s, strnlen(s, cap)); }

}  // namespace

Bridge::Bridge(std::unique_ptr<ipc::Regions> regions, int doorbell)
    : regions_(std::move(regions)),
      settings_(regions_->settings()),
      where_(bounded(settings_.cell_file, sizeof settings_.cell_file)),
      ch_(bounded(settings_.prefix, sizeof settings_.prefix)),
      epoch_(new_epoch()),
      doorbell_(doorbell),
      rec_(std::make_unique<ipc::CommandRecord>()),
      reply_(std::make_unique<ipc::ReplyRecord>()) {
  std::string url_error;
  transport_ = open_transport(bounded(settings_.url, sizeof settings_.url), url_error);
  if (!transport_)
    throw std::runtime_error(where_ + ":" + std::to_string(settings_.url_line) + ":" +
                             std::to_string(settings_.url_column) + ": key 'url': " + url_error);
  if (settings_.rate < 1 || settings_.rate > 1000)
    throw std::runtime_error(where_ + ": hmi: rate " + std::to_string(settings_.rate) +
                             " out of range");
  if (settings_.has_key) {
    Key k;
    std::memcpy(k.data(), settings_.key, k.size());
    key_ = k;
  }
  std::string err;
  if (!load_view(err)) throw std::runtime_error(where_ + ": hmi: " + err);
  sub_ = transport_->subscribe(ch_.cmd, [this](const ReceiveBuffer& rb, const std::string&) {
    // Replies are published after the handler returns, with the other
    // messages of the round.
    in_handler_ = true;
    on_command_bytes(rb.data, rb.data_size);
    in_handler_ = false;
  });
  regions_->control().bridge_pid.store(std::uint64_t(getpid()), std::memory_order_relaxed);
}

Bridge::~Bridge() {
  stop();
  if (sub_) transport_->unsubscribe(sub_);
}

void Bridge::attach(std::unique_ptr<ipc::Regions> regions) {
  regions_ = std::move(regions);
  pending_.clear();
  view_.reset();
  std::string err;
  load_view(err);
}

void Bridge::sync() {
  if (peer_) peer_();
}

bool Bridge::load_view(std::string& err) {
  // plcrun may be rewriting it (a rebuild under way): a few tries.
  for (int i = 0; i < 100; ++i) {
    auto v = std::make_unique<View>();
    auto cell = regions_->read_layout(v->generation, err);
    if (!cell) continue;
    v->cell = std::move(*cell);
    const ipc::CellLayout& c = v->cell;
    softplc_hmi::cell_description_t& d = v->desc;
    d.cell = c.cell;
    set_epoch(d, epoch_);
    d.layout_hash = static_cast<std::int64_t>(c.layout_hash);
    d.stop_commands_allowed = settings_.stop_commands != 0;
    d.key_required = key_.has_value();
    for (std::size_t k = 0; k < c.vars.size(); ++k) {
      const ipc::CellLayout::Var& var = c.vars[k];
      v->index[var.path] = std::uint32_t(k);
      softplc_hmi::var_desc_t vd;
      vd.path = var.path;
      vd.type = to_string(var.type);
      vd.address = var.address ? var.address->to_string() : "";
      vd.task = var.task >= 0 ? c.tasks[std::size_t(var.task)].name : "";
      vd.published = var.published;
      vd.writable = var.writable;
      vd.forceable = var.forceable;
      d.vars.push_back(vd);
    }
    d.n = int(d.vars.size());
    const auto now = Clock::now();
    for (std::size_t k = 0; k < c.slots.size(); ++k) {
      View::Slot s;
      s.last.resize(c.slots[k].items.size());
      s.requested = regions_->control().requests[k].load(std::memory_order_acquire);
      s.waiting =
          regions_->slot_header(c.slots[k]).filled.load(std::memory_order_acquire) != s.requested;
      s.asked = now;
      // Poll closely for two of the task's periods after asking (and a bit).
      const auto period = std::chrono::nanoseconds(c.tasks[c.slots[k].task].period_ns);
      s.fast_for = std::min<Clock::duration>(2 * period + std::chrono::milliseconds(2),
                                             std::chrono::milliseconds(200));
      v->slots.push_back(std::move(s));
    }
    v->devices.resize(c.devices.size());
    view_ = std::move(v);
    return true;
  }
  return false;
}

void Bridge::check_generation() {
  const std::uint64_t g = regions_->state().generation.load(std::memory_order_acquire);
  if (view_ && g == view_->generation) return;
  if (g & 1) return;  // plcrun is rewriting it: the next round
  std::string err;
  if (load_view(err)) publish_description();  // a rebuilt cell: clients see it at once
}

BridgeCounters Bridge::counters() const {
  std::lock_guard<std::mutex> lock(counters_mu_);
  return counters_;
}

void Bridge::count(std::uint64_t BridgeCounters::*counter, std::uint64_t n) {
  std::lock_guard<std::mutex> lock(counters_mu_);
  counters_.*counter += n;
  // Mirrored for plcrun's summary.
  ipc::BridgeCounters& m = regions_->control().bridge;
  m.published.store(counters_.published, std::memory_order_relaxed);
  m.dropped.store(counters_.dropped, std::memory_order_relaxed);
  m.commands.store(counters_.commands, std::memory_order_relaxed);
  m.refused.store(counters_.refused, std::memory_order_relaxed);
  m.bad_tag.store(counters_.bad_tag, std::memory_order_relaxed);
  m.replayed.store(counters_.replayed, std::memory_order_relaxed);
  m.stale.store(counters_.stale, std::memory_order_relaxed);
  m.malformed.store(counters_.malformed, std::memory_order_relaxed);
}

TagContext Bridge::tag_context(const std::string& channel) const {
  return {bounded(settings_.prefix, sizeof settings_.prefix),
          view_ ? view_->cell.cell : std::string(), channel};
}

softplc_hmi::cell_description_t Bridge::description() {
  if (!view_) return {};
  softplc_hmi::cell_description_t d = view_->desc;
  if (key_) sign(d, *key_, tag_context(ch_.desc));
  return d;
}

void Bridge::publish_description() {
  if (!view_) return;
  softplc_hmi::cell_description_t d = view_->desc;
  d.utime = utime_now();
  if (key_) sign(d, *key_, tag_context(ch_.desc));
  transport_->publish(ch_.desc, &d);
  if (tap_) tap_->on_description(d);
}

// ---------------------------------------------------------------- values

int Bridge::publish_slot(std::size_t s) {
  View& v = *view_;
  const ipc::CellLayout::Slot& slot = v.cell.slots[s];
  View::Slot& st = v.slots[s];
  const ipc::SlotHeader& h = regions_->slot_header(slot);
  const unsigned char* buf = regions_->slot_buffer(slot);
  const auto now = Clock::now();
  const bool full = now - st.last_full >= std::chrono::seconds(1);
  softplc_hmi::values_t m;
  softplc_hmi::trace_sample_t tr;
  m.utime = utime_now();
  m.cell = v.cell.cell;
  m.scan = static_cast<std::int64_t>(h.scan);
  m.plc_time_ns = h.plc_time_ns;
  m.scan_utime = h.copy_utime;
  m.task = v.cell.tasks[slot.task].name;
  m.full = full;
  tr.plc_time_ns = m.plc_time_ns;
  tr.scan = m.scan;
  tr.task = m.task;
  for (std::size_t i = 0; i < slot.items.size(); ++i) {
    const ipc::CellLayout::Item& it = slot.items[i];
    const VarType type = v.cell.vars[it.var].type;
    std::string text = value_text(type, buf + it.offset);
    tr.index.push_back(int(it.var));
    tr.value.push_back(value_number(type, buf + it.offset));
    if (!full && text == st.last[i]) continue;
    m.values.push_back({int(it.var), text, false});
    st.last[i] = std::move(text);
  }
  m.n = int(m.values.size());
  tr.n = int(tr.index.size());
  if (m.n == 0) return 0;
  transport_->publish(ch_.values, &m);
  transport_->publish(ch_.trace, &tr);
  if (tap_) tap_->on_values(m, tr);
  if (full) st.last_full = now;
  return 1;
}

int Bridge::poll_fills() {
  if (!view_) return 0;
  int sent = 0;
  for (std::size_t s = 0; s < view_->slots.size(); ++s) {
    View::Slot& st = view_->slots[s];
    if (!st.waiting) continue;
    const std::uint64_t filled =
        regions_->slot_header(view_->cell.slots[s]).filled.load(std::memory_order_acquire);
    if (filled != st.requested) continue;
    st.waiting = false;
    sent += publish_slot(s);
  }
  if (sent) count(&BridgeCounters::published, std::uint64_t(sent));
  return sent;
}

void Bridge::tick(Clock::time_point now) {
  if (!view_) return;
  // Ask every task whose last snapshot went out for its next scan's values.
  for (std::size_t s = 0; s < view_->slots.size(); ++s) {
    View::Slot& st = view_->slots[s];
    if (st.waiting) continue;
    st.requested += 1;
    regions_->control().requests[s].store(st.requested, std::memory_order_release);
    st.waiting = true;
    st.asked = now;
  }
  publish_device_alarms();
}

bool Bridge::fast_poll(Clock::time_point now) const {
  if (!pending_.empty()) return true;
  if (!view_) return false;
  for (const View::Slot& st : view_->slots)
    if (st.waiting && now - st.asked < st.fast_for) return true;
  return false;
}

int Bridge::service(int wait_ms) {
  // Bounded: at most 1000 waiting messages per round.
  for (int i = 0; i < 1000; ++i) {
    const int n = transport_->handle_timeout(i == 0 ? wait_ms : 0);
    flush_replies();
    if (n <= 0) break;
  }
  serve_local();
  sync();
  drain_replies();
  check_generation();
  const int sent = poll_fills();
  tick(Clock::now());
  // What this round published reaches subscribers of this process's own
  // transport (memq://) at its next dispatch: now, within the round. Commands
  // that come meanwhile are queued for plcrun's next round.
  for (int i = 0; i < 1000 && transport_->handle_timeout(0) > 0; ++i) flush_replies();
  flush_replies();
  return sent;
}

// ---------------------------------------------------------------- thread

void Bridge::start() {
  stop_ = false;
  publish_description();
  thread_ = std::thread([this] { run(stop_); });
}

void Bridge::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void Bridge::run(const std::atomic<bool>& stop) {
  const auto period = std::chrono::microseconds(1'000'000 / settings_.rate);
  auto next = Clock::now();
  auto next_slow = Clock::now();
  while (!stop.load()) {
    const auto now = Clock::now();
    check_generation();
    serve_local();
    drain_replies();
    poll_fills();
    expire_pending(now);
    if (now >= next) {
      // Late by whole periods: those ticks are dropped and counted, never caught up.
      const auto late = (now - next) / period;
      if (late > 0) count(&BridgeCounters::dropped, std::uint64_t(late));
      next += period * (late + 1);
      tick(now);
    }
    if (now >= next_slow) {
      publish_stats();
      publish_diagnostics();
      publish_description();  // also for clients of a replayed log
      next_slow = now + std::chrono::seconds(1);
    }
    if (fast_poll(now)) {
      // A snapshot or a reply is due any moment: look again in 100 us
      // (plcrun's scan thread makes no system call to wake us).
      for (int i = 0; i < 1000 && transport_->handle_timeout(0) > 0; ++i) flush_replies();
      flush_replies();
      const timespec ts{0, 100'000};
      nanosleep(&ts, nullptr);
      continue;
    }
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count();
    // With a tap (the web server) commands also come from submit(): look at
    // them every 10 ms rather than 100.
    transport_->handle_timeout(int(std::clamp<std::int64_t>(ms, 1, tap_ ? 10 : 100)));
    flush_replies();
  }
}

}  // namespace plc::hmi
