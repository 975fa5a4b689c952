#include "plc/hmi/bridge.hpp"

#include <fnmatch.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <thread>

#include "plc/hmi/checked_decode.hpp"
#include "plc/iec_literal.hpp"
#include "plc/thread_guard.hpp"
#include "softplc_hmi/diagnostics_t.hpp"
#include "softplc_hmi/stats_t.hpp"
#include "softplc_hmi/trace_sample_t.hpp"
#include "softplc_hmi/values_t.hpp"

namespace plc::hmi {

namespace {

std::int64_t utime_now() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

VarType type_for(io::AddrSize s) {
  switch (s) {
    case io::AddrSize::Bit:
      return VarType::BOOL;
    case io::AddrSize::Byte:
      return VarType::BYTE;
    case io::AddrSize::Word:
      return VarType::WORD;
    case io::AddrSize::DWord:
      return VarType::DWORD;
    default:
      return VarType::LWORD;
  }
}

// A value as a number for trace_sample_t (NaN for STRING).
double to_double(VarType t, const unsigned char* p) {
  auto get = [p]<class T>(T) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  switch (t) {
    case VarType::BOOL:
      return *reinterpret_cast<const bool*>(p) ? 1.0 : 0.0;
    case VarType::SINT:
      return get(std::int8_t{});
    case VarType::INT:
      return get(std::int16_t{});
    case VarType::DINT:
      return get(std::int32_t{});
    case VarType::LINT:
      return get(std::int64_t{});
    case VarType::USINT:
    case VarType::BYTE:
      return get(std::uint8_t{});
    case VarType::UINT:
    case VarType::WORD:
      return get(std::uint16_t{});
    case VarType::UDINT:
    case VarType::DWORD:
      return get(std::uint32_t{});
    case VarType::ULINT:
    case VarType::LWORD:
      return get(std::uint64_t{});
    case VarType::REAL:
      return get(float{});
    case VarType::LREAL:
      return get(double{});
    case VarType::TIME:
      return get(std::int64_t{}) / 1e9;  // seconds
    default:
      return std::nan("");
  }
}

}  // namespace

bool pattern_matches(const std::string& pattern, const std::string& text) {
  // Brackets are literal: they index arrays in the paths --list-vars prints
  // (`Cell.axes[0].pos`), and fnmatch would read `[0]` as a set of one
  // character. A backslash still escapes the next character (`\[0\]`, the
  // old way to write an index, keeps working).
  std::string glob;
  glob.reserve(pattern.size() + 4);
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (c == '\\' && i + 1 < pattern.size()) {
      glob += c;
      glob += pattern[++i];
    } else {
      if (c == '[' || c == ']') glob += '\\';
      glob += c;
    }
  }
  return fnmatch(glob.c_str(), text.c_str(), 0) == 0;
}

// What the bridge last reported of one device (publish_device_alarms).
struct Bridge::DeviceSeen {
  std::uint64_t changes = 0;  // DeviceLink::last_change().count
  io::DeviceState state = io::DeviceState::Offline;
  bool ever_online = false;
};

struct Bridge::Layout {
  const Runtime* rt = nullptr;  // the runtime attach() resolved this for
  std::vector<DeviceSeen> devices;
  std::string cell;
  softplc_hmi::cell_description_t desc;
  std::vector<std::unique_ptr<ScanSnapshot>> snaps;
  std::vector<std::vector<std::string>> last;  // per snapshot, per item: last text sent
  std::vector<std::string> task_names;
};

Bridge::Bridge(const HmiConfig& cfg, std::string cell_file)
    : cfg_(cfg), cell_file_(std::move(cell_file)), ch_(cfg.prefix.value), epoch_(new_epoch()) {
  std::string url_error;
  transport_ = open_transport(cfg_.url.value, url_error);
  if (!transport_) throw ConfigError(cell_file_, cfg_.url.mark, "key 'url': " + url_error);
  if (!cfg_.key_path.empty()) {
    std::string err;
    key_ = load_key(cfg_.key_path, err);
    if (!key_) throw ConfigError(cell_file_, cfg_.key_file.mark, "key 'key_file': " + err);
  }
  sub_ = transport_->subscribe(ch_.cmd, [this](const ReceiveBuffer& rb, const std::string&) {
    // Replies are published after the handler returns, with the other
    // messages of the round.
    in_handler_ = true;
    on_command_bytes(rb.data, rb.data_size);
    in_handler_ = false;
  });
}

Bridge::~Bridge() {
  stop();
  if (sub_) transport_->unsubscribe(sub_);
}

bool Bridge::may(const std::vector<Item<std::string>>& patterns, const std::string& name) const {
  for (const auto& p : patterns)
    if (pattern_matches(p.value, name)) return true;
  return false;
}

void Bridge::attach(Runtime& rt) {
  auto l = std::make_shared<Layout>();
  l->rt = &rt;
  l->cell = rt.cell_name();
  for (const DeviceRuntime& d : rt.devices()) {
    const io::DeviceLink& link = d.plugin->link(d.index);
    DeviceSeen seen;
    seen.changes = link.last_change().count;
    seen.state = link.state();
    seen.ever_online = seen.state == io::DeviceState::Online;
    l->devices.push_back(seen);
  }
  for (const auto& t : rt.tasks()) l->task_names.push_back(t->name);
  std::vector<std::vector<ScanSnapshot::Item>> per_task(rt.tasks().size());
  std::vector<bool> used(cfg_.publish.size() + cfg_.writable.size() + cfg_.forceable.size());
  auto note = [&](const std::string& name) {
    std::size_t k = 0;
    bool published = false;
    for (const auto* list : {&cfg_.publish, &cfg_.writable, &cfg_.forceable})
      for (const auto& p : *list) {
        const bool m = pattern_matches(p.value, name);
        if (m) used[k] = true;
        if (m && list == &cfg_.publish) published = true;
        ++k;
      }
    return published;
  };
  // The task whose scans see an address best: the one that exchanges its
  // device, else the fastest.
  auto task_of_address = [&rt](const io::IecAddress& a) {
    for (const DeviceRuntime& d : rt.devices()) {
      const io::IecAddress& base = a.area == io::Area::Input ? d.in : d.out;
      const std::size_t n = a.area == io::Area::Input ? d.sizes.input_bytes : d.sizes.output_bytes;
      if (a.area != io::Area::Memory && base.area == a.area && a.byte >= base.byte &&
          a.byte < base.byte + n && d.task >= 0)
        return d.task;
    }
    int best = 0;
    for (const auto& t : rt.tasks())
      if (t->period < rt.tasks()[std::size_t(best)]->period) best = int(t->order);
    return best;
  };
  auto add = [&](VarInfo v, bool published, bool read_only) {
    softplc_hmi::var_desc_t d;
    d.path = v.path;
    d.type = to_string(v.type);
    d.address = v.address ? v.address->to_string() : "";
    d.task = v.task >= 0 ? l->task_names[std::size_t(v.task)] : "";
    d.published = published && v.task >= 0;
    d.writable = !read_only && v.type != VarType::STRING && may(cfg_.writable, v.path);
    d.forceable = !read_only && v.type != VarType::STRING && may(cfg_.forceable, v.path);
    const int index = int(l->desc.vars.size());
    l->desc.vars.push_back(d);
    if (d.published) per_task[std::size_t(v.task)].push_back({v, 0, index});
  };
  for (const VarInfo& v : rt.vars().all()) add(v, note(v.path), v.read_only);
  // Patterns that are IEC addresses publish the address itself.
  for (const auto* list : {&cfg_.publish, &cfg_.writable, &cfg_.forceable})
    for (const auto& p : *list) {
      if (p.value.empty() || p.value[0] != '%') continue;
      auto r = io::parse_iec_address(p.value);
      if (!r.address) throw ConfigError(cell_file_, p.mark, "hmi: '" + p.value + "': " + r.error);
      if (!rt.image().contains(*r.address))
        throw ConfigError(cell_file_, p.mark, "hmi: " + p.value + " lies outside the image");
      bool seen = false;
      for (const auto& d : l->desc.vars) seen |= d.path == r.address->to_string();
      if (seen) continue;
      const int task = task_of_address(*r.address);
      VarInfo v;
      v.path = r.address->to_string();
      v.type = type_for(r.address->size);
      v.address = *r.address;
      v.order = rt.byte_order();
      v.task = task;
      // Read from the task's own copy of the image: consistent within its scan.
      v.image_ptr = rt.tasks()[std::size_t(task)]->image.at(*r.address);
      add(v, note(v.path), false);
    }
  std::size_t k = 0;
  for (const auto* list : {&cfg_.publish, &cfg_.writable, &cfg_.forceable})
    for (const auto& p : *list) {
      if (!used[k++])
        throw ConfigError(cell_file_, p.mark,
                          "hmi: pattern '" + p.value +
                              "' matches no variable (plcrun CONFIG --list-vars lists them)");
    }
  l->desc.cell = l->cell;
  set_epoch(l->desc, epoch_);
  l->desc.layout_hash = static_cast<std::int64_t>(rt.layout_hash());
  l->desc.stop_commands_allowed = cfg_.stop_commands.value;
  l->desc.key_required = key_.has_value();
  l->desc.n = int(l->desc.vars.size());
  for (std::size_t t = 0; t < per_task.size(); ++t) {
    if (per_task[t].empty()) continue;
    auto s = std::make_unique<ScanSnapshot>(int(t), std::move(per_task[t]));
    l->last.emplace_back(s->items().size());
    s->request();
    ScanSnapshot* sp = s.get();
    // The observer keeps the layout alive for as long as the runtime lives.
    rt.add_scan_observer([sp, l, task = t](const TaskRuntime& tr, const ScanContext& ctx) {
      if (tr.order == task) sp->on_scan_end(tr, ctx);
    });
    l->snaps.push_back(std::move(s));
  }
  std::lock_guard<std::mutex> lock(layout_mu_);
  layout_ = std::move(l);
}

softplc_hmi::cell_description_t Bridge::description() {
  softplc_hmi::cell_description_t d;
  {
    std::lock_guard<std::mutex> lock(layout_mu_);
    if (!layout_) return d;
    d = layout_->desc;
  }
  if (key_) sign(d, *key_, tag_context(ch_.desc));
  return d;
}

TagContext Bridge::tag_context(const std::string& channel) {
  std::lock_guard<std::mutex> lock(layout_mu_);
  return {cfg_.prefix.value, layout_ ? layout_->cell : std::string(), channel};
}

BridgeCounters Bridge::counters() const {
  std::lock_guard<std::mutex> lock(counters_mu_);
  return counters_;
}

int Bridge::publish_values(bool full) {
  std::shared_ptr<Layout> l;
  {
    std::lock_guard<std::mutex> lock(layout_mu_);
    l = layout_;
  }
  if (!l) return 0;
  int sent = 0;
  for (std::size_t s = 0; s < l->snaps.size(); ++s) {
    ScanSnapshot& snap = *l->snaps[s];
    const unsigned char* buf = snap.ready();
    if (!buf) continue;
    softplc_hmi::values_t m;
    softplc_hmi::trace_sample_t tr;
    m.utime = utime_now();
    m.cell = l->cell;
    m.scan = static_cast<std::int64_t>(snap.scan());
    m.plc_time_ns = snap.plc_time().count();
    m.scan_utime = snap.copy_utime();
    m.task = l->task_names[std::size_t(snap.task())];
    m.full = full;
    tr.plc_time_ns = m.plc_time_ns;
    tr.scan = m.scan;
    tr.task = m.task;
    for (std::size_t i = 0; i < snap.items().size(); ++i) {
      const auto& it = snap.items()[i];
      // Values of a run are packed, not aligned: an aligned copy first.
      alignas(8) unsigned char p[sizeof(STRING)];
      std::memcpy(p, buf + it.offset,
                  it.var.type == VarType::STRING ? sizeof(STRING) : size_of(it.var.type));
      std::string text = format_value(it.var.type, p);
      tr.index.push_back(it.index);
      tr.value.push_back(to_double(it.var.type, p));
      if (!full && text == l->last[s][i]) continue;
      m.values.push_back({it.index, text, false});
      l->last[s][i] = std::move(text);
    }
    snap.request();  // the next scan copies again
    m.n = int(m.values.size());
    tr.n = int(tr.index.size());
    if (m.n == 0) continue;
    transport_->publish(ch_.values, &m);
    transport_->publish(ch_.trace, &tr);
    ++sent;
  }
  std::lock_guard<std::mutex> lock(counters_mu_);
  counters_.published += std::uint64_t(sent);
  return sent;
}

int Bridge::service(int wait_ms) {
  // Bounded: at most 1000 waiting messages per round.
  for (int i = 0; i < 1000; ++i) {
    const int n = transport_->handle_timeout(i == 0 ? wait_ms : 0);
    flush_replies();
    if (n <= 0) break;
  }
  const auto now = std::chrono::steady_clock::now();
  const bool full = now - last_full_ >= std::chrono::seconds(1);
  const int sent = publish_values(full);
  publish_device_alarms();
  if (full && sent > 0) last_full_ = now;
  return sent;
}

void Bridge::publish_description() {
  std::shared_ptr<Layout> l;
  {
    std::lock_guard<std::mutex> lock(layout_mu_);
    l = layout_;
  }
  if (!l) return;
  softplc_hmi::cell_description_t d = l->desc;
  d.utime = utime_now();
  if (key_) sign(d, *key_, {cfg_.prefix.value, l->cell, ch_.desc});
  transport_->publish(ch_.desc, &d);
}

template <class F>
void Bridge::with_runtime(F f) {
  if (!dbg_) return;
  // The runtime may be rebuilt (goto): read it only between commands, and
  // skip this round when the console is running one.
  std::unique_lock<std::recursive_mutex> session(dbg_->session_mutex(), std::try_to_lock);
  if (session.owns_lock()) f(dbg_->runtime());
}

void Bridge::publish_stats() {
  softplc_hmi::stats_t m;
  m.utime = utime_now();
  for (std::size_t i = 0; i < epoch_.size(); ++i) m.epoch[i] = std::int8_t(epoch_[i]);
  with_runtime([&m](Runtime& rt) {
    m.cell = rt.cell_name();
    for (const auto& t : rt.tasks()) {
      const TaskStats s = t->stats.snapshot();
      softplc_hmi::task_stat_t ts;
      ts.name = t->name;
      ts.period_ns = t->period.count();
      ts.scans = std::int64_t(s.scans);
      ts.overruns = std::int64_t(s.overruns);
      ts.scan_ns_min = std::int64_t(s.scan_ns.min());
      ts.scan_ns_avg = std::int64_t(s.scan_ns.mean());
      ts.scan_ns_max = std::int64_t(s.scan_ns.max());
      ts.stop_reason = s.stop_reason;
      m.tasks.push_back(ts);
    }
  });
  m.n = int(m.tasks.size());
  const BridgeCounters c = counters();
  m.published = std::int64_t(c.published);
  m.dropped = std::int64_t(c.dropped);
  m.commands = std::int64_t(c.commands);
  m.refused = std::int64_t(c.refused);
  m.bad_tag = std::int64_t(c.bad_tag);
  m.replayed = std::int64_t(c.replayed);
  m.stale = std::int64_t(c.stale);
  m.malformed = std::int64_t(c.malformed);
  for (const auto& [name, count] : transport_->counters().named()) {
    m.transport_counter.push_back(name);
    m.transport_count.push_back(std::int64_t(count));
  }
  m.n_transport = int(m.transport_count.size());
  transport_->publish(ch_.stats, &m);
}

namespace {

std::string device_alarm_text(const std::string& task, io::DeviceState from, io::DeviceState to,
                              std::uint64_t scan, TIME time) {
  std::string s = std::string(io::to_string(from)) + " -> " + io::to_string(to);
  if (scan == 0) return s + " (its scan is not known: several changes within one bridge round)";
  char b[96];
  std::snprintf(b, sizeof b, " at scan %llu of task %s (t=%.3f s)",
                static_cast<unsigned long long>(scan), task.c_str(),
                std::chrono::duration<double>(time).count());
  return s + b;
}

softplc_hmi::alarm_t device_alarm(const Runtime& rt, const DeviceRuntime& d, io::DeviceState from,
                                  io::DeviceState to, std::uint64_t scan, TIME time,
                                  bool ever_online) {
  softplc_hmi::alarm_t a{};
  a.source = "device " + d.name;
  a.task = rt.tasks()[std::size_t(d.task)]->name;
  a.text = device_alarm_text(a.task, from, to, scan, time);
  a.kind = to != io::DeviceState::Online ? "device_lost"
           : ever_online                 ? "device_back"
                                         : "device_online";
  a.active = to != io::DeviceState::Online;
  a.from_state = io::to_string(from);
  a.to_state = io::to_string(to);
  a.scan = std::int64_t(scan);
  a.plc_time_ns = time.count();
  a.utime = utime_now();
  return a;
}

}  // namespace

int Bridge::publish_device_alarms() {
  std::shared_ptr<Layout> l;
  {
    std::lock_guard<std::mutex> lock(layout_mu_);
    l = layout_;
  }
  if (!l) return 0;
  std::vector<softplc_hmi::alarm_t> out;
  with_runtime([&](Runtime& rt) {
    if (&rt != l->rt || rt.devices().size() != l->devices.size()) return;  // not attached yet
    for (std::size_t i = 0; i < l->devices.size(); ++i) {
      const DeviceRuntime& d = rt.devices()[i];
      const io::DeviceLink::StateChange c = d.plugin->link(d.index).last_change();
      DeviceSeen& seen = l->devices[i];
      if (c.count == seen.changes || c.torn) continue;  // torn: the next round reads it
      // More than one change since the last round: the one before the last
      // is reported without its scan (the link keeps the last one only).
      if (c.count - seen.changes > 1 && seen.state != c.from) {
        out.push_back(device_alarm(rt, d, seen.state, c.from, 0, TIME(0), seen.ever_online));
        seen.ever_online |= c.from == io::DeviceState::Online;
      }
      out.push_back(device_alarm(rt, d, c.from, c.to, c.scan, c.time, seen.ever_online));
      seen.changes = c.count;
      seen.state = c.to;
      seen.ever_online |= c.to == io::DeviceState::Online;
    }
  });
  for (const auto& a : out) transport_->publish(ch_.alarm, &a);
  return int(out.size());
}

void Bridge::publish_diagnostics() {
  softplc_hmi::diagnostics_t m;
  m.utime = utime_now();
  with_runtime([&m](Runtime& rt) {
    m.cell = rt.cell_name();
    for (const DeviceRuntime& d : rt.devices()) {
      const io::DeviceLink& link = d.plugin->link(d.index);
      const io::DeviceLink::StateChange c = link.last_change();
      softplc_hmi::device_t dv;
      dv.name = d.name;
      dv.plugin = d.plugin_name;
      dv.task = d.task >= 0 ? rt.tasks()[std::size_t(d.task)]->name : "";
      dv.input = d.in.to_string();
      dv.output = d.out.to_string();
      dv.in_bytes = int(d.sizes.input_bytes);
      dv.out_bytes = int(d.sizes.output_bytes);
      dv.state = io::to_string(link.live_state());
      dv.diagnostics = d.plugin->diagnostics(d.index);
      dv.changes = std::int64_t(c.count);
      m.devices.push_back(dv);
      // Active: the device as its task's scans see it is not online.
      const io::DeviceState seen = link.state();
      if (seen != io::DeviceState::Online) {
        softplc_hmi::alarm_t a = c.count && !c.torn
                                     ? device_alarm(rt, d, c.from, c.to, c.scan, c.time, true)
                                     : device_alarm(rt, d, seen, seen, 0, TIME(0), false);
        if (!c.count) a.text = std::string(io::to_string(seen)) + " since the start";
        if (c.count && c.torn) a.text = io::to_string(seen);
        m.alarms.push_back(a);
      }
    }
    for (const auto& t : rt.tasks()) {
      const TaskStats s = t->stats.snapshot();
      if (s.stop_reason.empty()) continue;
      softplc_hmi::alarm_t a{};
      a.source = "task " + t->name;
      a.text = s.stop_reason;
      a.kind = "task_stopped";
      a.active = true;
      a.task = t->name;
      a.utime = m.utime;
      m.alarms.push_back(a);
    }
  });
  {
    std::lock_guard<std::mutex> lock(counters_mu_);
    m.alarms.insert(m.alarms.end(), start_alarms_.begin(), start_alarms_.end());
  }
  m.n_devices = int(m.devices.size());
  m.n_alarms = int(m.alarms.size());
  transport_->publish(ch_.diag, &m);
}

void Bridge::add_start_alarm(const std::string& kind, const std::string& source,
                             const std::string& text) {
  softplc_hmi::alarm_t a{};
  a.source = source;
  a.text = text;
  a.kind = kind;
  a.active = true;
  a.utime = utime_now();
  std::lock_guard<std::mutex> lock(counters_mu_);
  start_alarms_.push_back(a);
}

void Bridge::start() {
  stop_ = false;
  publish_description();
  // The bridge faces the operator network; its failure must not touch the
  // cell: it is said (and counted: plcrun's exit code is 1), the HMI sees
  // the bridge's updates stop (its stale indication), and the scans run on.
  thread_ = std::thread([this] {
    run_guarded(
        "hmi bridge", [this] { run(); }, [](std::string_view) {});
  });
}

void Bridge::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void Bridge::run() {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::microseconds(1'000'000 / cfg_.rate.value);
  auto next = Clock::now() + period;
  auto next_slow = Clock::now();
  while (!stop_.load()) {
    const auto now = Clock::now();
    if (now < next) {
      const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count();
      transport_->handle_timeout(int(std::max<std::int64_t>(1, std::min<std::int64_t>(ms, 100))));
      flush_replies();
      continue;
    }
    // Late by whole periods: those ticks are dropped and counted, never caught up.
    const auto late = (now - next) / period;
    if (late > 0) {
      std::lock_guard<std::mutex> lock(counters_mu_);
      counters_.dropped += std::uint64_t(late);
    }
    next += period * (late + 1);
    service(0);
    if (now >= next_slow) {
      publish_stats();
      publish_diagnostics();
      publish_description();  // also for clients of a replayed log
      next_slow = now + std::chrono::seconds(1);
    }
  }
}

// ------------------------------------------------------------- commands

void Bridge::on_command_bytes(const void* data, std::size_t size) {
  softplc_hmi::command_t c;
  if (size > 65536 || !checked_decode(data, size, c)) {
    std::lock_guard<std::mutex> lock(counters_mu_);
    ++counters_.malformed;
    return;
  }
  softplc_hmi::reply_t r = serve(c);
  r.request_id = c.request_id;
  r.client = c.client;
  r.n = int(r.values.size());
  // Every reply is signed, refusals too: with a random request id (plcctl)
  // a signed reply to someone else's request answers nothing of its own.
  set_epoch(r, epoch_);
  if (key_) sign(r, *key_, tag_context(ch_.reply));
  if (in_handler_ && pending_.size() < 1000)
    pending_.push_back(std::move(r));
  else if (!in_handler_)
    transport_->publish(ch_.reply, &r);
}

void Bridge::flush_replies() {
  std::vector<softplc_hmi::reply_t> out;
  out.swap(pending_);
  for (const auto& r : out) transport_->publish(ch_.reply, &r);
}

softplc_hmi::reply_t Bridge::serve(const softplc_hmi::command_t& c) {
  softplc_hmi::reply_t r;
  auto refuse = [&](std::string why, std::uint64_t BridgeCounters::*counter) {
    r.ok = false;
    r.refusal = std::move(why);
    std::lock_guard<std::mutex> lock(counters_mu_);
    ++(counters_.*counter);
    return r;
  };
  // describe changes nothing and is how a client learns the epoch it must
  // sign for: it needs no tag (what it publishes is signed).
  if (c.verb != "describe") {
    std::string why = authenticate(c);
    if (!why.empty()) {
      r.ok = false;
      r.refusal = std::move(why);
      return r;
    }
  }
  const std::string& v = c.verb;
  const auto& a = c.args;
  if (v == "describe") {
    publish_description();
    r.ok = true;
    r.text = "described on " + ch_.desc;
    return r;
  }
  if (!dbg_) return refuse("this cell serves no commands (no debugger)", &BridgeCounters::refused);
  const bool stops =
      v == "pause" || v == "step" || v == "continue" || v == "break" || v == "delete";
  if (stops && !cfg_.stop_commands.value)
    return refuse("'" + v + "' is not allowed: the cell's hmi: stop_commands is false",
                  &BridgeCounters::refused);
  // Up to 200 tries 1 ms apart rather than try_lock_for: a timed lock is
  // pthread_mutex_clocklock, which ThreadSanitizer does not intercept (it
  // then reports every unlock of the session mutex as a wrong-thread unlock).
  std::unique_lock<std::recursive_mutex> session(dbg_->session_mutex(), std::defer_lock);
  for (int i = 0; i < 200 && !session.try_lock(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (!session.owns_lock())
    return refuse("busy: the debugger console is running a command", &BridgeCounters::refused);
  debug::Debugger::Reply d{false, ""};
  if (v == "read") {
    if (a.empty()) return refuse("read: name at least one variable", &BridgeCounters::refused);
    for (const auto& val : dbg_->read(a)) {
      softplc_hmi::var_value_t o;
      o.path = val.name;
      o.error = val.error;
      if (val.error.empty()) {
        o.type = to_string(val.type);
        o.address = val.address ? val.address->to_string() : "";
        o.text = val.text;
        o.forced = val.forced;
      }
      r.values.push_back(o);
    }
    r.ok = true;
    std::lock_guard<std::mutex> lock(counters_mu_);
    ++counters_.commands;
    return r;
  } else if (v == "write" || v == "force") {
    if (a.size() != 2) return refuse(v + ": needs NAME VALUE", &BridgeCounters::refused);
    const bool ok = v == "write" ? may(cfg_.writable, a[0]) : may(cfg_.forceable, a[0]);
    if (!ok)
      return refuse(v + " " + a[0] + ": not allowed (the cell's hmi: " +
                        (v == "write" ? "writable" : "forceable") + " patterns do not match it)",
                    &BridgeCounters::refused);
    d = v == "write" ? dbg_->write(a[0], a[1]) : dbg_->force(a[0], a[1]);
  } else if (v == "unforce") {
    if (a.empty() || a.size() > 2 || (a.size() == 2 && a[1] != "restore"))
      return refuse("unforce: needs NAME [restore]", &BridgeCounters::refused);
    if (a[0] == "all") return unforce_all(a.size() == 2);
    if (!may(cfg_.forceable, a[0]))
      return refuse("unforce " + a[0] + ": not allowed (not forceable)", &BridgeCounters::refused);
    d = dbg_->unforce(a[0], a.size() == 2);
  } else if (v == "pause") {
    d = dbg_->pause();
  } else if (v == "step") {
    std::uint64_t n = 1;
    if (!a.empty()) {
      char* end = nullptr;
      n = std::strtoull(a[0].c_str(), &end, 10);
      if (a[0].empty() || *end || n < 1 || n > 1'000'000)
        return refuse("step: '" + a[0] + "' is not a count from 1 to 1000000",
                      &BridgeCounters::refused);
    }
    d = dbg_->step(n);
  } else if (v == "continue") {
    d = dbg_->continue_running();
  } else if (v == "break") {
    if (a.size() != 1) return refuse("break: needs one CONDITION", &BridgeCounters::refused);
    d = dbg_->add_breakpoint(a[0]);
  } else if (v == "delete") {
    if (a.size() != 1) return refuse("delete: needs ID|all", &BridgeCounters::refused);
    d = dbg_->delete_breakpoint(a[0]);
  } else {
    return refuse("unknown verb '" + v + "'", &BridgeCounters::refused);
  }
  r.text = d.text;
  if (!d.ok) return refuse(d.text, &BridgeCounters::refused);
  r.ok = true;
  std::lock_guard<std::mutex> lock(counters_mu_);
  ++counters_.commands;
  return r;
}

std::string Bridge::authenticate(const softplc_hmi::command_t& c) {
  if (!key_) return "";
  auto counted = [this](std::string why, std::uint64_t BridgeCounters::*counter) {
    std::lock_guard<std::mutex> lock(counters_mu_);
    ++(counters_.*counter);
    return why;
  };
  // The tag first: only then is the epoch the command carries its sender's.
  if (!verify(c, *key_, tag_context(ch_.cmd)))
    return counted(
        "bad tag: the HMAC does not verify (no tag, another key, or signed for another cell, "
        "prefix or channel)",
        &BridgeCounters::bad_tag);
  if (epoch_of(c) != epoch_)
    return counted("stale epoch: signed for epoch " + to_hex(epoch_of(c)) +
                       ", this bridge started since with epoch " + to_hex(epoch_) +
                       " (a client sends it again for the reply's epoch)",
                   &BridgeCounters::stale);
  switch (replay_.check(c.client, c.counter)) {
    case ReplayGuard::Verdict::fresh:
      break;
    case ReplayGuard::Verdict::replayed:
      return counted("replayed: counter " + std::to_string(c.counter) +
                         " is not above the last one of client '" + c.client + "'",
                     &BridgeCounters::replayed);
    case ReplayGuard::Verdict::below_floor:
      return counted("replayed: counter " + std::to_string(c.counter) + " of client '" + c.client +
                         "' is not above " + std::to_string(replay_.floor()) +
                         ", the last counter of a client the bridge forgot (it tracks " +
                         std::to_string(ReplayGuard::kMaxClients) +
                         " clients per epoch; is this client's clock behind?)",
                     &BridgeCounters::replayed);
  }
  replay_.accept(c.client, c.counter);
  return "";
}

// `unforce all` from a client releases what the forceable patterns match
// and keeps every other force (the console's), in one step of the debugger.
softplc_hmi::reply_t Bridge::unforce_all(bool restore) {
  softplc_hmi::reply_t r;
  std::vector<std::string> kept;
  const debug::Debugger::Reply d = dbg_->unforce_if(
      [&](const std::string& name) {
        if (may(cfg_.forceable, name)) return true;
        kept.push_back(name);
        return false;
      },
      restore);
  std::string kept_text;
  for (const auto& k : kept)
    kept_text += "kept " + k + " (the cell's hmi: forceable patterns do not match it)\n";
  std::lock_guard<std::mutex> lock(counters_mu_);
  if (!d.ok) {
    r.ok = false;
    r.refusal = "unforce all: no force that this client may release\n" + kept_text;
    ++counters_.refused;
    return r;
  }
  r.ok = true;
  r.text = d.text + kept_text;
  ++counters_.commands;
  return r;
}

}  // namespace plc::hmi
