#include "plc/profibus/slave/dp_slave.hpp"

#include <algorithm>
#include <cstdio>

#include "plc/profibus/dp/cfg.hpp"
#include "plc/profibus/dp/services.hpp"

namespace plc::profibus::slave {

using namespace fdl;

const char* to_string(SlaveState s) {
  switch (s) {
    case SlaveState::WaitPrm:
      return "Wait_Prm";
    case SlaveState::WaitCfg:
      return "Wait_Cfg";
    case SlaveState::DataExch:
      return "Data_Exch";
  }
  return "?";
}

DpSlave::DpSlave(const SlaveConfig& cfg, std::unique_ptr<io::DeviceModel> model, link::Line& line)
    : cfg_(cfg), model_(std::move(model)), line_(line) {
  inputs_.assign(cfg_.input_bytes, 0);
  frozen_inputs_.assign(cfg_.input_bytes, 0);
  outputs_.assign(cfg_.output_bytes, 0);
  applied_.assign(cfg_.output_bytes, 0);
  model_in_.assign(model_->input_size(), 0);
  model_out_.assign(model_->output_size(), 0);
}

void DpSlave::tick(TIME now) {
  std::array<std::uint8_t, 512> buf{};
  for (int i = 0; i < 64; ++i) {
    const std::size_t n = line_.receive(buf);
    if (n == 0) break;
    rx_.push({buf.data(), n});
  }
  Telegram t;
  const std::uint64_t dropped = rx_.dropped_bytes();
  while (rx_.next(t)) {
    if (t.format == Format::Token || t.format == Format::ShortAck || !t.request()) continue;
    if (t.da != cfg_.address && t.da != kBroadcast) continue;
    if (faults_.silent || !model_->answering()) continue;
    on_request(t, now);
  }
  counters_.bad_bytes += rx_.dropped_bytes() - dropped;

  // Watchdog: no telegram from the master for the Set_Prm time.
  if (state_ != SlaveState::WaitPrm && watchdog_ms_ > 0 && !faults_.ignore_watchdog &&
      now - last_master_ > std::chrono::milliseconds(watchdog_ms_)) {
    ++counters_.watchdog_expiries;
    to_wait_prm();
    model_->io_connection_lost();
  }

  // The device runs all the time; it sees outputs only in Data_Exch.
  const TIME dt = stepped_ ? now - last_step_ : TIME(0);
  stepped_ = true;
  last_step_ = now;
  std::fill(model_out_.begin(), model_out_.end(), 0);
  if (state_ == SlaveState::DataExch)
    std::copy_n(applied_.begin(), std::min(applied_.size(), model_out_.size()), model_out_.begin());
  model_->step(now, dt, model_out_, model_in_);
  std::copy_n(model_in_.begin(), std::min(model_in_.size(), inputs_.size()), inputs_.begin());
}

void DpSlave::to_wait_prm() {
  state_ = SlaveState::WaitPrm;
  master_ = 0xFF;
  watchdog_ms_ = 0;
  freeze_ = sync_ = false;
  std::fill(outputs_.begin(), outputs_.end(), 0);
  std::fill(applied_.begin(), applied_.end(), 0);
  diag_changed_ = true;
  last_fcb_ = -1;
}

void DpSlave::answer(const Telegram& t) {
  last_answer_len_ = encode(t, last_answer_);
  if (last_answer_len_) line_.send({last_answer_.data(), last_answer_len_});
}

void DpSlave::answer_sc() { answer(make_short_ack()); }

void DpSlave::reply_data(const Telegram& req, std::int16_t dsap, std::int16_t ssap,
                         std::uint8_t function, std::span<const std::uint8_t> data) {
  answer(make_data(req.sa, cfg_.address, static_cast<std::uint8_t>(kStationSlave | function), dsap,
                   ssap, data));
}

void DpSlave::refuse(const Telegram& req, std::uint8_t function) {
  ++counters_.refused;
  reply_data(req, req.ssap, req.dsap, function, {});
}

void DpSlave::on_request(const Telegram& t, TIME now) {
  ++counters_.requests;
  const std::uint8_t f = t.function();
  if (f == kReqFdlStatus && t.dsap < 0) {
    reply_data(t, -1, -1, kResOk, {});
    return;
  }
  const bool srd = f == kReqSrdHigh || f == kReqSrdLow;
  const bool sdn = f == kReqSdnHigh || f == kReqSdnLow;
  if (t.sa == master_) last_master_ = now;
  if (t.da == kBroadcast) {
    if (sdn && t.dsap == dp::kSapGlobalControl) global_control(t);
    return;
  }
  if (sdn && t.dsap == dp::kSapGlobalControl) {
    global_control(t);
    return;
  }
  if (!srd) {
    if (!sdn) refuse(t, kResNoService);
    return;
  }
  // A repetition of the last request (its answer was lost): the same answer.
  if ((t.fc & kFcFcv) && t.sa == master_ && last_fcb_ == ((t.fc & kFcFcb) ? 1 : 0) &&
      last_answer_len_ > 0) {
    ++counters_.repeats;
    line_.send({last_answer_.data(), last_answer_len_});
    return;
  }
  if (t.sa == master_ || master_ == 0xFF) last_fcb_ = (t.fc & kFcFcb) ? 1 : 0;
  if (t.dsap < 0 && t.ssap < 0) {
    data_exchange(t);
    return;
  }
  if (t.ssap != dp::kSapMaster) {
    refuse(t, kResNoService);
    return;
  }
  switch (t.dsap) {
    case dp::kSapSlaveDiag: {
      ++counters_.diag_reads;
      const auto d = diagnosis(t.sa);
      reply_data(t, t.ssap, t.dsap, kResDataLow, d);
      if (t.sa == master_ || master_ == 0xFF) diag_changed_ = false;
      return;
    }
    case dp::kSapSetPrm:
      set_prm(t, now);
      return;
    case dp::kSapChkCfg:
      chk_cfg(t);
      return;
    case dp::kSapGetCfg: {
      const auto& c = accepted_cfg_.empty() ? cfg_.cfg : accepted_cfg_;
      reply_data(t, t.ssap, t.dsap, kResDataLow, c);
      return;
    }
    default:
      refuse(t, kResNoService);
      return;
  }
}

void DpSlave::set_prm(const Telegram& t, TIME now) {
  ++counters_.set_prm;
  const auto p = dp::SetPrm::decode(t.du());
  if (master_ != 0xFF && master_ != t.sa && (!p || (p->station_status & dp::kPrmLockReq))) {
    answer_sc();  // locked by another master: acknowledged, not taken
    return;
  }
  answer_sc();
  diag_changed_ = true;
  if (p && !(p->station_status & dp::kPrmLockReq) && (p->station_status & dp::kPrmUnlockReq)) {
    to_wait_prm();
    return;
  }
  const bool ok = p && p->ident == cfg_.ident && p->user.size() == cfg_.user_prm_len &&
                  (!(p->station_status & dp::kPrmFreezeReq) || cfg_.freeze_supported) &&
                  (!(p->station_status & dp::kPrmSyncReq) || cfg_.sync_supported);
  if (!ok) {
    ++counters_.prm_faults;
    to_wait_prm();
    prm_fault_ = true;
    return;
  }
  prm_fault_ = cfg_fault_ = not_supported_ = false;
  master_ = t.sa;
  last_fcb_ = (t.fc & kFcFcb) ? 1 : 0;
  last_master_ = now;
  group_ = p->group;
  watchdog_ms_ = p->watchdog_ms();
  freeze_enabled_ = (p->station_status & dp::kPrmFreezeReq) != 0;
  sync_enabled_ = (p->station_status & dp::kPrmSyncReq) != 0;
  freeze_ = sync_ = false;
  state_ = SlaveState::WaitCfg;
}

bool DpSlave::cfg_ok(std::span<const std::uint8_t> cfg) const {
  if (cfg_.modules.empty())
    return std::equal(cfg.begin(), cfg.end(), cfg_.cfg.begin(), cfg_.cfg.end());
  if (cfg.empty() || cfg.size() > cfg_.max_modules) return false;
  for (const std::uint8_t b : cfg)
    if (std::find(cfg_.modules.begin(), cfg_.modules.end(), b) == cfg_.modules.end()) return false;
  const auto s = dp::cfg_sizes(cfg);
  return s && s->input_bytes == cfg_.input_bytes && s->output_bytes == cfg_.output_bytes;
}

void DpSlave::chk_cfg(const Telegram& t) {
  ++counters_.chk_cfg;
  answer_sc();
  if (t.sa != master_ || state_ == SlaveState::WaitPrm) return;  // wants parameters first
  diag_changed_ = true;
  if (!cfg_ok(t.du())) {
    ++counters_.cfg_faults;
    to_wait_prm();
    cfg_fault_ = true;
    return;
  }
  accepted_cfg_.assign(t.du().begin(), t.du().end());
  cfg_fault_ = false;
  state_ = SlaveState::DataExch;
}

void DpSlave::global_control(const Telegram& t) {
  ++counters_.global_controls;
  if (t.sa != master_ || state_ != SlaveState::DataExch || t.length != 2) return;
  const dp::GlobalControl gc{t.data[0], t.data[1]};
  if (!gc.addresses(group_)) return;
  if (gc.command & dp::kGcClearData) {
    std::fill(outputs_.begin(), outputs_.end(), 0);
    std::fill(applied_.begin(), applied_.end(), 0);
  }
  // Freeze_Mode and Sync_Mode are in the diagnosis: a change answers the
  // next Data_Exchange high priority, so the master reads it.
  const bool was_frozen = freeze_, was_synced = sync_;
  if (gc.command & (dp::kGcFreeze | dp::kGcUnfreeze)) {
    if (!freeze_enabled_) {
      not_supported_ = diag_changed_ = true;
    } else if (gc.command & dp::kGcUnfreeze) {
      freeze_ = false;  // Unfreeze wins over Freeze in the same command
    } else {
      freeze_ = true;
      frozen_inputs_ = inputs_;
    }
  }
  if (gc.command & (dp::kGcSync | dp::kGcUnsync)) {
    if (!sync_enabled_) {
      not_supported_ = diag_changed_ = true;
    } else if (gc.command & dp::kGcUnsync) {
      sync_ = false;
      applied_ = outputs_;
    } else {
      sync_ = true;
      applied_ = outputs_;
    }
  }
  if (freeze_ != was_frozen || sync_ != was_synced) diag_changed_ = true;
}

void DpSlave::data_exchange(const Telegram& t) {
  if (state_ != SlaveState::DataExch || t.sa != master_ || t.length != cfg_.output_bytes) {
    refuse(t, kResNoService);
    return;
  }
  ++counters_.data_exchanges;
  std::copy_n(t.data.begin(), t.length, outputs_.begin());
  if (!sync_) applied_ = outputs_;
  const auto& in = freeze_ ? frozen_inputs_ : inputs_;
  const bool high = diag_changed_ || faults_.stat_diag || !faults_.ext.empty();
  if (in.empty()) {
    reply_data(t, -1, -1, high ? kResDataHigh : kResDataLow, {});
  } else {
    reply_data(t, -1, -1, high ? kResDataHigh : kResDataLow, in);
  }
}

std::vector<std::uint8_t> DpSlave::diagnosis(std::uint8_t asking) const {
  dp::Diagnosis d;
  d.ident = cfg_.ident;
  d.master = master_;
  if (state_ != SlaveState::DataExch) d.status1 |= dp::kDiag1StationNotReady;
  if (cfg_fault_) d.status1 |= dp::kDiag1CfgFault;
  if (prm_fault_) d.status1 |= dp::kDiag1PrmFault;
  if (not_supported_) d.status1 |= dp::kDiag1NotSupported;
  if (master_ != 0xFF && master_ != asking) d.status1 |= dp::kDiag1MasterLock;
  if (!faults_.ext.empty()) {
    d.status1 |= dp::kDiag1ExtDiag;
    const std::size_t room = std::max<std::size_t>(cfg_.max_diag_len, 6) - 6;
    d.ext.assign(faults_.ext.begin(), faults_.ext.begin() + static_cast<std::ptrdiff_t>(std::min(
                                                                room, faults_.ext.size())));
    if (faults_.ext.size() > room) d.status3 |= dp::kDiag3ExtDiagOverflow;
  }
  if (state_ == SlaveState::WaitPrm) d.status2 |= dp::kDiag2PrmReq;
  if (faults_.stat_diag) d.status2 |= dp::kDiag2StatDiag;
  if (watchdog_ms_ > 0) d.status2 |= dp::kDiag2WdOn;
  if (freeze_) d.status2 |= dp::kDiag2FreezeMode;
  if (sync_) d.status2 |= dp::kDiag2SyncMode;
  return d.encode();
}

std::string DpSlave::describe() const {
  char b[320];
  std::snprintf(b, sizeof b,
                "address %u %s master %u; requests %llu data-exchanges %llu diag %llu set-prm %llu "
                "(faults %llu) chk-cfg %llu (faults %llu) global-control %llu watchdog-expiries "
                "%llu repeats %llu refused %llu bad-bytes %llu",
                cfg_.address, to_string(state_), master_,
                static_cast<unsigned long long>(counters_.requests),
                static_cast<unsigned long long>(counters_.data_exchanges),
                static_cast<unsigned long long>(counters_.diag_reads),
                static_cast<unsigned long long>(counters_.set_prm),
                static_cast<unsigned long long>(counters_.prm_faults),
                static_cast<unsigned long long>(counters_.chk_cfg),
                static_cast<unsigned long long>(counters_.cfg_faults),
                static_cast<unsigned long long>(counters_.global_controls),
                static_cast<unsigned long long>(counters_.watchdog_expiries),
                static_cast<unsigned long long>(counters_.repeats),
                static_cast<unsigned long long>(counters_.refused),
                static_cast<unsigned long long>(counters_.bad_bytes));
  return b;
}

}  // namespace plc::profibus::slave
