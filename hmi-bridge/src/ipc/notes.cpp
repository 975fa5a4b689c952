#include "plc/hmi/ipc/notes.hpp"

#include "plc/hmi/ipc/wire.hpp"

namespace plc::hmi::ipc {

std::vector<unsigned char> StatsNote::encode() const {
  WireOut w;
  w.u32(std::uint32_t(tasks.size()));
  for (const Task& t : tasks) {
    w.u64(t.scans);
    w.u64(t.overruns);
    w.u64(t.skipped);
    w.i64(t.scan_ns_min);
    w.i64(t.scan_ns_avg);
    w.i64(t.scan_ns_max);
    w.str(t.stop_reason);
  }
  return w.bytes();
}

std::optional<StatsNote> StatsNote::decode(const std::vector<unsigned char>& b) {
  WireIn r(b.data(), b.size());
  StatsNote n;
  n.tasks.resize(r.count(52));
  for (Task& t : n.tasks) {
    t.scans = r.u64();
    t.overruns = r.u64();
    t.skipped = r.u64();
    t.scan_ns_min = r.i64();
    t.scan_ns_avg = r.i64();
    t.scan_ns_max = r.i64();
    t.stop_reason = r.str();
  }
  if (!r.at_end()) return std::nullopt;
  return n;
}

std::vector<unsigned char> DiagNote::encode() const {
  WireOut w;
  w.u32(std::uint32_t(devices.size()));
  for (const Device& d : devices) {
    w.u8(d.live_state);
    w.u8(d.seen_state);
    w.u64(d.changes);
    w.u8(d.from);
    w.u8(d.to);
    w.u8(d.torn ? 1 : 0);
    w.u64(d.scan);
    w.i64(d.time_ns);
    w.str(d.diagnostics);
  }
  return w.bytes();
}

std::optional<DiagNote> DiagNote::decode(const std::vector<unsigned char>& b) {
  WireIn r(b.data(), b.size());
  DiagNote n;
  n.devices.resize(r.count(33));
  for (Device& d : n.devices) {
    d.live_state = r.u8();
    d.seen_state = r.u8();
    d.changes = r.u64();
    d.from = r.u8();
    d.to = r.u8();
    d.torn = r.u8() != 0;
    d.scan = r.u64();
    d.time_ns = r.i64();
    d.diagnostics = r.str();
    if (d.live_state > 2 || d.seen_state > 2 || d.from > 2 || d.to > 2) r.fail();
  }
  if (!r.at_end()) return std::nullopt;
  return n;
}

std::vector<unsigned char> OutageNote::encode() const {
  WireOut w;
  w.u64(total);
  w.u32(std::uint32_t(recent.size()));
  for (const Outage& o : recent) {
    w.u64(o.number);
    w.str(o.cause);
    w.i64(o.down_utime);
    w.i64(o.up_utime);
  }
  return w.bytes();
}

std::optional<OutageNote> OutageNote::decode(const std::vector<unsigned char>& b) {
  WireIn r(b.data(), b.size());
  OutageNote n;
  n.total = r.u64();
  n.recent.resize(r.count(28));
  if (n.recent.size() > kKept) r.fail();
  for (Outage& o : n.recent) {
    o.number = r.u64();
    o.cause = r.str(256);
    o.down_utime = r.i64();
    o.up_utime = r.i64();
  }
  if (!r.at_end()) return std::nullopt;
  return n;
}

}  // namespace plc::hmi::ipc
