#include "plc/profibus/master/dp_master.hpp"

#include <algorithm>
#include <cstdio>

#include "plc/profibus/dp/cfg.hpp"

namespace plc::profibus::master {

using namespace fdl;

const char* to_string(SlaveState s) {
  switch (s) {
    case SlaveState::Waiting:
      return "waiting";
    case SlaveState::Starting:
      return "starting";
    case SlaveState::Online:
      return "data exchange";
    case SlaveState::Fault:
      return "fault";
  }
  return "?";
}

DpMaster::DpMaster(const MasterConfig& cfg, link::Line* line) : line_(line) { configure(cfg); }

void DpMaster::configure(const MasterConfig& cfg) {
  cfg_ = cfg;
  reply_timeout_ = std::max(cfg_.bus.bits(cfg_.bus.tsl), cfg_.min_reply_timeout);
  gap_next_ = static_cast<std::uint8_t>(cfg_.address + 1);
}

std::size_t DpMaster::add(const SlaveEntry& e) {
  auto s = std::make_unique<Slave>();
  s->cfg = e;
  s->in.assign(e.input_bytes, 0);
  s->out.assign(e.output_bytes, 0);
  if (!e.active) {
    dp::Diagnosis d;
    d.status2 = dp::kDiag2Always1 | dp::kDiag2Deactivated;
    d.ident = e.prm.ident;
    post_diagnosis(*s, d);
    s->last_error = "deactivated";
  }
  slaves_.push_back(std::move(s));
  return slaves_.size() - 1;
}

void DpMaster::global_control(std::uint8_t command, std::uint8_t groups) {
  gc_command_ = command;
  gc_groups_ = groups;
  gc_pending_ = true;
}

void DpMaster::send(const Telegram& t, TIME now) {
  const std::size_t n = encode(t, tx_);
  if (n == 0) return;
  line_->send({tx_.data(), n});
  ++sent_;
  if (capture_) capture_->record(now.count(), true, {tx_.data(), n}, t);
}

void DpMaster::request(Kind k, std::size_t slave, Telegram t, TIME now) {
  if (k != Kind::FdlStatus) {
    Slave& s = *slaves_[slave];
    // Frame count bit: the first request after a start FCB=1 FCV=0, then
    // alternating with FCV=1. A retry repeats the stored bytes.
    if (s.fcb < 0) {
      s.fcb = 1;
      t.fc |= kFcFcb;
    } else {
      s.fcb ^= 1;
      t.fc |= static_cast<std::uint8_t>(kFcFcv | (s.fcb ? kFcFcb : 0));
    }
  }
  pending_.kind = k;
  pending_.slave = slave;
  pending_.da = t.da;
  pending_.retries = 0;
  // A GAP request waits at most 2 ms (a PC line's reply timeout is tens of
  // ms) and is not repeated: a station it misses is found at a later
  // rotation, and a long wait for an empty address would stretch the cycle.
  pending_.deadline =
      now + (k == Kind::FdlStatus ? std::min<TIME>(reply_timeout_, std::chrono::milliseconds(2))
                                  : reply_timeout_);
  pending_.first_sent = pending_.last_sent = now;
  pending_.length = encode(t, pending_.bytes);
  line_->send({pending_.bytes.data(), pending_.length});
  ++sent_;
  if (capture_) capture_->record(now.count(), true, {pending_.bytes.data(), pending_.length}, t);
}

void DpMaster::tick(TIME now) {
  std::array<std::uint8_t, 512> buf{};
  for (int i = 0; i < 64; ++i) {
    const std::size_t n = line_->receive(buf);
    if (n == 0) break;
    rx_.push({buf.data(), n});
  }
  Telegram t;
  std::span<const std::uint8_t> raw;
  const std::uint64_t dropped = rx_.dropped_bytes();
  while (rx_.next(t, &raw)) {
    if (capture_) capture_->record(now.count(), false, raw, t);
    const bool ours = t.format == Format::ShortAck || (t.format != Format::Token && !t.request() &&
                                                       t.da == cfg_.address && t.sa == pending_.da);
    if (awaiting() && ours) {
      on_answer(t, now);
    } else if (now <= quiet_until_ && t.format != Format::Token && !t.request() &&
               (t.format == Format::ShortAck || t.sa == quiet_da_)) {
      ++counters_.late_answers;
      if (capture_) capture_->note(now.count(), "late answer to a repeated request: dropped");
    } else {
      ++counters_.unexpected;
    }
  }
  if (rx_.dropped_bytes() != dropped) {
    counters_.bad_bytes += rx_.dropped_bytes() - dropped;
    if (capture_) capture_->note(now.count(), std::string("bytes dropped: ") + rx_.last_error());
  }
  if (awaiting() && now >= pending_.deadline) on_timeout(now);
  if (now < quiet_until_) return;
  for (std::size_t guard = 0; guard < slaves_.size() + 8 && !awaiting(); ++guard)
    if (!next_transaction(now)) break;
}

bool DpMaster::next_transaction(TIME now) {
  if (!in_cycle_) {
    if (now < next_cycle_) return false;
    in_cycle_ = true;
    cursor_ = 0;
    cycle_start_ = now;
  }
  const std::size_t n = slaves_.size();
  while (cursor_ < n) {
    const std::size_t i = cursor_++;
    Slave& s = *slaves_[i];
    const std::uint8_t da = s.cfg.address;
    const std::uint8_t srd = kFcRequest | kReqSrdHigh;
    if (!s.cfg.active) continue;
    if (s.state == SlaveState::Waiting || s.state == SlaveState::Fault) {
      if (now < s.next_try) continue;
      start_slave(s, now);
    }
    if (s.state == SlaveState::Online && !s.read_diag) {
      request(Kind::DataExchange, i, make_data(da, cfg_.address, srd, -1, -1, s.out), now);
      return true;
    }
    switch (s.step) {
      case Step::SetPrm: {
        const auto prm = s.cfg.prm.encode();
        request(Kind::SetPrm, i,
                make_data(da, cfg_.address, srd, dp::kSapSetPrm, dp::kSapMaster, prm), now);
        return true;
      }
      case Step::ChkCfg:
        request(Kind::ChkCfg, i,
                make_data(da, cfg_.address, srd, dp::kSapChkCfg, dp::kSapMaster, s.cfg.cfg), now);
        return true;
      default:
        request(Kind::Diag, i, make_data(da, cfg_.address, srd, dp::kSapSlaveDiag, dp::kSapMaster),
                now);
        return true;
    }
  }
  if (cursor_ == n) {
    ++cursor_;
    if (gc_pending_) {
      gc_pending_ = false;
      ++counters_.global_controls;
      const dp::GlobalControl gc{gc_command_, gc_groups_};
      const auto b = gc.encode();
      send(make_data(kBroadcast, cfg_.address, kFcRequest | kReqSdnHigh, dp::kSapGlobalControl,
                     dp::kSapMaster, b),
           now);
    }
  }
  if (cursor_ == n + 1) {
    ++cursor_;
    ++rotations_;
    if (cfg_.bus.gap_factor > 0 && rotations_ % cfg_.bus.gap_factor == 0) {
      // The next address of the GAP that is not one of our slaves.
      for (int k = 0; k < 128; ++k) {
        const std::uint8_t a = gap_next_;
        gap_next_ = static_cast<std::uint8_t>(a >= cfg_.bus.hsa ? 0 : a + 1);
        const bool slave = std::any_of(slaves_.begin(), slaves_.end(),
                                       [&](const auto& s) { return s->cfg.address == a; });
        if (a == cfg_.address || a > cfg_.bus.hsa || slave) continue;
        ++counters_.gap_requests;
        request(Kind::FdlStatus, 0, make_data(a, cfg_.address, kFcRequest | kReqFdlStatus, -1, -1),
                now);
        return true;
      }
    }
  }
  // The end of the cycle: the token to itself.
  if (cfg_.token) {
    send(make_token(cfg_.address, cfg_.address), now);
    ++counters_.tokens;
  }
  ++counters_.cycles;
  in_cycle_ = false;
  last_cycle_ = now - cycle_start_;
  next_cycle_ = cycle_start_ + cfg_.cycle;
  if (next_cycle_ < now) next_cycle_ = now;  // late: no burst of cycles
  return false;                              // the next cycle starts at next_cycle_
}

void DpMaster::start_slave(Slave& s, TIME now) {
  (void)now;
  s.state = SlaveState::Starting;
  s.step = Step::Diag1;
  s.fcb = -1;
  s.read_diag = false;
  s.not_ready = 0;
  ++s.counters.startups;
}

void DpMaster::on_timeout(TIME now) {
  if (pending_.kind != Kind::FdlStatus && pending_.retries < cfg_.bus.max_retry) {
    ++pending_.retries;
    pending_.deadline = now + reply_timeout_;
    pending_.last_sent = now;
    line_->send({pending_.bytes.data(), pending_.length});
    ++sent_;
    ++slaves_[pending_.slave]->counters.retries;
    if (capture_) capture_->note(now.count(), "no answer: retry");
    return;
  }
  const Kind k = pending_.kind;
  pending_.kind = Kind::None;
  if (k == Kind::FdlStatus) return;  // nobody at that address
  Slave& s = *slaves_[pending_.slave];
  char b[96];
  std::snprintf(b, sizeof b, "no answer (%d retries, slot time %lld us)", cfg_.bus.max_retry,
                static_cast<long long>(reply_timeout_.count() / 1000));
  lose(s, now, b);
}

void DpMaster::on_answer(const Telegram& t, TIME now) {
  const Kind k = pending_.kind;
  pending_.kind = Kind::None;
  if (pending_.retries > 0) {
    // The slave got the request more than once and answers each (a
    // repetition carries the same FCB: the same answer again). Taking this
    // answer as the first one's, the last repetition's may come as late
    // after it was sent: as long as this one took.
    quiet_until_ = pending_.last_sent + (now - pending_.first_sent);
    quiet_da_ = pending_.da;
  }
  if (k == Kind::FdlStatus) {
    if (t.format != Format::ShortAck && (t.fc & 0x30) != kStationSlave && on_other_master)
      on_other_master(t.sa);
    return;
  }
  Slave& s = *slaves_[pending_.slave];
  const bool sc = t.format == Format::ShortAck;
  const std::uint8_t f = sc ? kResOk : t.function();
  char b[128];
  switch (k) {
    case Kind::Diag: {
      ++s.counters.diag_reads;
      const auto d =
          (!sc && t.ssap == dp::kSapSlaveDiag) ? dp::Diagnosis::decode(t.du()) : std::nullopt;
      if (!d) {
        std::snprintf(b, sizeof b, "Slave_Diag answered %s without a diagnosis",
                      sc ? "SC" : "a telegram");
        post_invalid_response(s);
        return lose(s, now, b);
      }
      return handle_diag(s, *d, now);
    }
    case Kind::SetPrm:
    case Kind::ChkCfg:
      if (f != kResOk) {
        std::snprintf(b, sizeof b, "%s refused (FC 0x%02X)",
                      k == Kind::SetPrm ? "Set_Prm" : "Chk_Cfg", t.fc);
        ++s.counters.refused;
        return fault(s, now, b);
      }
      s.step = k == Kind::SetPrm ? Step::ChkCfg : Step::Diag2;
      return;
    case Kind::DataExchange: {
      if (f == kResNoService || f == kResNoResource || f == kResUserError || f == kResNoData) {
        // The slave left Data_Exch (its watchdog, a restart): start it up again.
        ++s.counters.refused;
        std::snprintf(b, sizeof b,
                      "Data_Exchange refused (FC 0x%02X): the slave lost its parameters", t.fc);
        lose(s, now, b);
        s.next_try = now;
        return;
      }
      const std::size_t got = sc ? 0 : t.length;
      if (got != s.in.size()) {
        ++s.counters.wrong_size;
        std::snprintf(b, sizeof b, "Data_Exchange answer of %zu bytes, configured %zu", got,
                      s.in.size());
        post_invalid_response(s);
        return fault(s, now, b);
      }
      std::copy_n(t.data.begin(), got, s.in.begin());
      ++s.counters.data_exchanges;
      if (f == kResDataHigh || f == kResDataHighNoRes) s.read_diag = true;
      return;
    }
    default:
      return;
  }
}

void DpMaster::handle_diag(Slave& s, const dp::Diagnosis& d, TIME now) {
  post_diagnosis(s, d);
  char b[128];
  if (d.ident != s.cfg.prm.ident && !(d.status1 & dp::kDiag1PrmFault)) {
    std::snprintf(b, sizeof b, "Ident_Number 0x%04X, configured 0x%04X", d.ident, s.cfg.prm.ident);
    return fault(s, now, b);
  }
  if ((d.status1 & dp::kDiag1MasterLock) && d.master != cfg_.address) {
    std::snprintf(b, sizeof b, "Master_Lock: parametrised by master %u", d.master);
    return fault(s, now, b);
  }
  if (s.step == Step::Diag1) {
    s.step = Step::SetPrm;
    return;
  }
  if (d.status1 & dp::kDiag1PrmFault) {
    ++s.counters.prm_faults;
    return fault(s, now, "Prm_Fault: the slave refuses the parameters (" + d.text() + ")");
  }
  if (d.status1 & dp::kDiag1CfgFault) {
    ++s.counters.cfg_faults;
    return fault(
        s, now,
        "Cfg_Fault: the slave refuses Chk_Cfg " + dp::hex(s.cfg.cfg) + " (" + d.text() + ")");
  }
  if (d.status1 & dp::kDiag1NotSupported) {
    // A function the slave does not have (Freeze or Sync without its
    // Set_Prm request): no number of diagnosis reads clears it, a new
    // Set_Prm does.
    return fault(s, now,
                 "Not_Supported: the slave refuses a requested function (" + d.text() + ")");
  }
  if (d.status2 & dp::kDiag2PrmReq) {
    // Lost its parameters (watchdog, restart): parametrise it again now.
    if (s.state == SlaveState::Online) {
      lose(s, now, "Prm_Req: the slave wants new parameters");
      s.next_try = now;
      return;
    }
    s.step = Step::SetPrm;
    return;
  }
  if (d.ready()) {
    s.read_diag = false;
    if (s.state != SlaveState::Online) online(s);
    return;
  }
  // Station_Not_Ready or Stat_Diag: keep reading the diagnosis.
  if (s.state == SlaveState::Online) {
    s.state = SlaveState::Starting;
    s.step = Step::Diag2;
    std::fill(s.in.begin(), s.in.end(), 0);
    s.link.set_state(io::DeviceState::Offline);
    s.last_error = "not ready: " + d.text();
    changed(s);
  }
  s.read_diag = true;
  if (++s.not_ready > 1000) return fault(s, now, "not ready for 1000 diagnosis reads: " + d.text());
}

void DpMaster::post_diagnosis(Slave& s, const dp::Diagnosis& d) {
  const bool same = s.diag_known && s.diag.status1 == d.status1 && s.diag.status2 == d.status2 &&
                    s.diag.status3 == d.status3 && s.diag.ext == d.ext;
  s.diag = d;
  s.diag_known = true;
  if (same) return;
  // FBs see the DP diagnosis as a device alarm: type 1 (diagnosis), the
  // first four diagnosis bytes big-endian in `data`; `appears` while a
  // fault or Ext_Diag is reported.
  io::DeviceAlarm a;
  a.type = 1;
  a.data = static_cast<std::uint32_t>(d.status1) << 24 |
           static_cast<std::uint32_t>(d.status2) << 16 |
           static_cast<std::uint32_t>(d.status3) << 8 | d.master;
  a.appears = (d.status1 & (dp::kDiag1CfgFault | dp::kDiag1PrmFault | dp::kDiag1ExtDiag |
                            dp::kDiag1NotSupported | dp::kDiag1StationNonExistent |
                            dp::kDiag1InvalidSlaveResponse | dp::kDiag1MasterLock)) != 0 ||
              (d.status2 & dp::kDiag2StatDiag) != 0;
  s.link.post_alarm(a);
}

// Invalid_Slave_Response is the master's own bit (EN 50170: an
// implausible answer): the slave's last diagnosis with that bit alone in
// the first byte, so FBs and the HMI line see why the slave was dropped.
void DpMaster::post_invalid_response(Slave& s) {
  dp::Diagnosis d = s.diag;
  d.status1 = dp::kDiag1InvalidSlaveResponse;
  d.status2 = dp::kDiag2Always1;
  d.status3 = 0;
  d.ext.clear();
  post_diagnosis(s, d);
}

void DpMaster::online(Slave& s) {
  s.state = SlaveState::Online;
  s.step = Step::Exchange;
  s.read_diag = false;
  s.not_ready = 0;
  s.last_error.clear();
  s.link.set_state(io::DeviceState::Online);
  changed(s);
}

void DpMaster::lose(Slave& s, TIME now, const std::string& why) {
  if (s.state == SlaveState::Online) ++s.counters.losses;
  const bool was = s.state != SlaveState::Waiting;
  s.state = SlaveState::Waiting;
  s.step = Step::Diag1;
  s.last_error = why;
  std::fill(s.in.begin(), s.in.end(), 0);  // invalid inputs never look like data
  s.link.set_state(io::DeviceState::Offline);
  s.next_try = now + cfg_.retry;
  if (why.rfind("no answer", 0) == 0) {
    dp::Diagnosis d = s.diag;
    d.status1 = dp::kDiag1StationNonExistent;
    d.status2 = dp::kDiag2Always1;
    post_diagnosis(s, d);
  }
  if (was) changed(s);
}

void DpMaster::fault(Slave& s, TIME now, const std::string& why) {
  const bool was = s.state != SlaveState::Fault || s.last_error != why;
  if (s.state == SlaveState::Online) ++s.counters.losses;
  s.state = SlaveState::Fault;
  s.step = Step::Diag1;
  s.last_error = why;
  std::fill(s.in.begin(), s.in.end(), 0);
  s.link.set_state(io::DeviceState::Fault);
  s.next_try = now + cfg_.retry;
  if (was) changed(s);
}

void DpMaster::changed(const Slave& s) {
  if (!on_change) return;
  for (std::size_t i = 0; i < slaves_.size(); ++i)
    if (slaves_[i].get() == &s) on_change(i, s.state, s.last_error);
}

std::string DpMaster::diagnostics(std::size_t i) const {
  const Slave& s = *slaves_[i];
  const SlaveCounters& c = s.counters;
  char b[512];
  std::snprintf(
      b, sizeof b,
      "profibus address %u %s; data-exchanges %llu retries %llu losses %llu startups %llu "
      "diag-reads %llu prm-faults %llu cfg-faults %llu wrong-size %llu refused %llu; "
      "bus cycle %lld us",
      s.cfg.address, to_string(s.state), static_cast<unsigned long long>(c.data_exchanges),
      static_cast<unsigned long long>(c.retries), static_cast<unsigned long long>(c.losses),
      static_cast<unsigned long long>(c.startups), static_cast<unsigned long long>(c.diag_reads),
      static_cast<unsigned long long>(c.prm_faults), static_cast<unsigned long long>(c.cfg_faults),
      static_cast<unsigned long long>(c.wrong_size), static_cast<unsigned long long>(c.refused),
      static_cast<long long>(last_cycle_.count() / 1000));
  std::string r = b;
  if (s.diag_known) r += "; diag: " + s.diag.text();
  if (!s.last_error.empty()) r += "; last: " + s.last_error;
  return r;
}

}  // namespace plc::profibus::master
