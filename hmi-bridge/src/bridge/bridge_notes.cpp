// Statistics, diagnostics and alarms: what plcrun's host refreshes in the
// shared memory (plc/hmi/ipc/notes.hpp), published as stats_t,
// diagnostics_t and alarm_t.
#include <cstdio>
#include <ctime>

#include "bridge_view.hpp"
#include "plc/hmi/bridge.hpp"
#include "plc/hmi/utime.hpp"
#include "softplc_hmi/diagnostics_t.hpp"
#include "softplc_hmi/stats_t.hpp"

namespace plc::hmi {

namespace {

// io::DeviceState's names (plc/io/device_link.hpp), without linking it.
const char* state_name(std::uint8_t s) {
  static const char* const names[] = {"offline", "online", "fault"};
  return s < 3 ? names[s] : "unknown";
}
constexpr std::uint8_t kOnline = 1;

std::string device_alarm_text(const std::string& task, std::uint8_t from, std::uint8_t to,
                              std::uint64_t scan, std::int64_t time_ns) {
  std::string s = std::string(state_name(from)) + " -> " + state_name(to);
  if (scan == 0) return s + " (its scan is not known: several changes within one bridge round)";
  char b[96];
  std::snprintf(b, sizeof b, " at scan %llu of task %s (t=%.3f s)",
                static_cast<unsigned long long>(scan), task.c_str(), double(time_ns) / 1e9);
  return s + b;
}

softplc_hmi::alarm_t device_alarm(const ipc::CellLayout& cell, std::size_t device,
                                  std::uint8_t from, std::uint8_t to, std::uint64_t scan,
                                  std::int64_t time_ns, bool ever_online) {
  const ipc::CellLayout::Device& d = cell.devices[device];
  softplc_hmi::alarm_t a{};
  a.source = "device " + d.name;
  a.task = d.task >= 0 ? cell.tasks[std::size_t(d.task)].name : "";
  a.text = device_alarm_text(a.task, from, to, scan, time_ns);
  a.kind = to != kOnline ? "device_lost" : ever_online ? "device_back" : "device_online";
  a.active = to != kOnline;
  a.from_state = state_name(from);
  a.to_state = state_name(to);
  a.scan = std::int64_t(scan);
  a.plc_time_ns = time_ns;
  a.utime = utime_now();
  return a;
}

std::string local_time(std::int64_t utime) {
  const std::time_t t = std::time_t(utime / 1'000'000);
  std::tm tm{};
  localtime_r(&t, &tm);
  char b[32];
  std::strftime(b, sizeof b, "%H:%M:%S", &tm);
  return b;
}

// An outage of the bridge as plcrun noted it, once it was back.
softplc_hmi::alarm_t outage_alarm(const ipc::OutageNote::Outage& o) {
  softplc_hmi::alarm_t a{};
  a.source = "hmi";
  a.kind = "hmi_lost";
  a.active = false;
  char b[64];
  std::snprintf(b, sizeof b, "%.2f s", double(o.up_utime - o.down_utime) / 1e6);
  a.text = o.cause + " at " + local_time(o.down_utime) + "; the HMI was down " + b + " (outage " +
           std::to_string(o.number) + ")";
  a.from_state = "lost";
  a.to_state = "back";
  a.utime = o.up_utime;
  return a;
}

}  // namespace

void Bridge::publish_stats() {
  sync();
  softplc_hmi::stats_t m;
  m.utime = utime_now();
  std::vector<unsigned char> bytes;
  if (view_) {
    m.cell = view_->cell.cell;
    std::optional<ipc::StatsNote> note;
    if (regions_->stats().read(bytes)) note = ipc::StatsNote::decode(bytes);
    if (note && note->tasks.size() == view_->cell.tasks.size())
      for (std::size_t i = 0; i < note->tasks.size(); ++i) {
        const ipc::StatsNote::Task& s = note->tasks[i];
        softplc_hmi::task_stat_t ts;
        ts.name = view_->cell.tasks[i].name;
        ts.period_ns = view_->cell.tasks[i].period_ns;
        ts.scans = std::int64_t(s.scans);
        ts.overruns = std::int64_t(s.overruns);
        ts.scan_ns_min = s.scan_ns_min;
        ts.scan_ns_avg = s.scan_ns_avg;
        ts.scan_ns_max = s.scan_ns_max;
        ts.stop_reason = s.stop_reason;
        m.tasks.push_back(ts);
      }
  }
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
  for (std::size_t i = 0; i < epoch_.size(); ++i) m.epoch[i] = std::int8_t(epoch_[i]);
  for (const auto& [name, n] : transport_->counters().named()) {
    m.transport_counter.push_back(name);
    m.transport_count.push_back(std::int64_t(n));
  }
  m.n_transport = int(m.transport_count.size());
  transport_->publish(ch_.stats, &m);
  if (tap_) tap_->on_stats(m);
}

void Bridge::publish_diagnostics() {
  sync();
  softplc_hmi::diagnostics_t m;
  m.utime = utime_now();
  std::vector<unsigned char> bytes;
  if (view_) {
    const ipc::CellLayout& cell = view_->cell;
    m.cell = cell.cell;
    std::optional<ipc::DiagNote> diag;
    if (regions_->diag().read(bytes)) diag = ipc::DiagNote::decode(bytes);
    if (diag && diag->devices.size() == cell.devices.size())
      for (std::size_t i = 0; i < cell.devices.size(); ++i) {
        const ipc::CellLayout::Device& d = cell.devices[i];
        const ipc::DiagNote::Device& n = diag->devices[i];
        softplc_hmi::device_t dv;
        dv.name = d.name;
        dv.plugin = d.plugin;
        dv.task = d.task >= 0 ? cell.tasks[std::size_t(d.task)].name : "";
        dv.input = d.input;
        dv.output = d.output;
        dv.in_bytes = d.in_bytes;
        dv.out_bytes = d.out_bytes;
        dv.state = state_name(n.live_state);
        dv.diagnostics = n.diagnostics;
        dv.changes = std::int64_t(n.changes);
        m.devices.push_back(dv);
        // Active: the device as its task's scans see it is not online.
        if (n.seen_state != kOnline) {
          softplc_hmi::alarm_t a =
              n.changes && !n.torn ? device_alarm(cell, i, n.from, n.to, n.scan, n.time_ns, true)
                                   : device_alarm(cell, i, n.seen_state, n.seen_state, 0, 0, false);
          if (!n.changes) a.text = std::string(state_name(n.seen_state)) + " since the start";
          if (n.changes && n.torn) a.text = state_name(n.seen_state);
          m.alarms.push_back(a);
        }
      }
    std::optional<ipc::StatsNote> stats;
    if (regions_->stats().read(bytes)) stats = ipc::StatsNote::decode(bytes);
    if (stats && stats->tasks.size() == cell.tasks.size())
      for (std::size_t i = 0; i < cell.tasks.size(); ++i) {
        if (stats->tasks[i].stop_reason.empty()) continue;
        softplc_hmi::alarm_t a{};
        a.source = "task " + cell.tasks[i].name;
        a.text = stats->tasks[i].stop_reason;
        a.kind = "task_stopped";
        a.active = true;
        a.task = cell.tasks[i].name;
        a.utime = m.utime;
        m.alarms.push_back(a);
      }
    for (const ipc::CellLayout::Alarm& s : cell.start_alarms) {
      softplc_hmi::alarm_t a{};
      a.source = s.source;
      a.text = s.text;
      a.kind = s.kind;
      a.active = true;
      a.utime = s.utime;
      m.alarms.push_back(a);
    }
  }
  // The bridge's own outages that plcrun keeps (the last OutageNote::kKept),
  // for a client that was not listening when they were announced: each as
  // an hmi_lost alarm, no longer active (the bridge publishing this is up).
  std::optional<ipc::OutageNote> outages;
  if (regions_->outages().read(bytes)) outages = ipc::OutageNote::decode(bytes);
  if (outages)
    for (const ipc::OutageNote::Outage& o : outages->recent)
      if (o.up_utime != 0) m.alarms.push_back(outage_alarm(o));
  m.n_devices = int(m.devices.size());
  m.n_alarms = int(m.alarms.size());
  transport_->publish(ch_.diag, &m);
  if (tap_) tap_->on_diagnostics(m);
}

int Bridge::publish_device_alarms() {
  sync();
  if (!view_) return 0;
  std::vector<softplc_hmi::alarm_t> out;
  std::vector<unsigned char> bytes;
  std::optional<ipc::DiagNote> diag;
  if (regions_->diag().read(bytes)) diag = ipc::DiagNote::decode(bytes);
  View& v = *view_;
  if (diag && diag->devices.size() == v.devices.size()) {
    if (!v.devices_known) {
      // What the devices were when this bridge came up: no alarm for it.
      for (std::size_t i = 0; i < v.devices.size(); ++i) {
        v.devices[i].changes = diag->devices[i].changes;
        v.devices[i].state = diag->devices[i].seen_state;
        v.devices[i].ever_online = v.devices[i].state == kOnline || diag->devices[i].changes > 0;
      }
      v.devices_known = true;
    }
    for (std::size_t i = 0; i < v.devices.size(); ++i) {
      const ipc::DiagNote::Device& c = diag->devices[i];
      View::DeviceSeen& seen = v.devices[i];
      if (c.changes == seen.changes || c.torn) continue;  // torn: the next round reads it
      // More than one change since the last round: the one before the last
      // is reported without its scan (the link keeps the last one only).
      if (c.changes - seen.changes > 1 && seen.state != c.from) {
        out.push_back(device_alarm(v.cell, i, seen.state, c.from, 0, 0, seen.ever_online));
        seen.ever_online |= c.from == kOnline;
      }
      out.push_back(device_alarm(v.cell, i, c.from, c.to, c.scan, c.time_ns, seen.ever_online));
      seen.changes = c.changes;
      seen.state = c.to;
      seen.ever_online |= c.to == kOnline;
    }
  }
  // The bridge's own outages, noted by plcrun, once each when it is back.
  std::optional<ipc::OutageNote> outages;
  if (regions_->outages().read(bytes)) outages = ipc::OutageNote::decode(bytes);
  if (outages) {
    auto& announced = regions_->control().announced_outages;
    std::uint64_t upto = announced.load(std::memory_order_relaxed);
    for (const ipc::OutageNote::Outage& o : outages->recent) {
      if (o.number <= upto || o.up_utime == 0) continue;
      out.push_back(outage_alarm(o));
      upto = o.number;
    }
    announced.store(upto, std::memory_order_relaxed);
  }
  for (const auto& a : out) {
    transport_->publish(ch_.alarm, &a);
    if (tap_) tap_->on_alarm(a);
  }
  return int(out.size());
}

}  // namespace plc::hmi
