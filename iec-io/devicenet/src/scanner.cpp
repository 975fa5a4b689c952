#include "plc/devicenet/scanner.hpp"

#include <algorithm>
#include <cstdio>

#include "plc/devicenet/identifiers.hpp"
#include "plc/devicenet/objects.hpp"
#include "plc/io/explicit_message.hpp"

namespace plc::devicenet {

namespace em = io::explicit_msg;

const char* to_string(ScanState s) {
  switch (s) {
    case ScanState::Waiting:
      return "waiting";
    case ScanState::Releasing:
      return "releasing";
    case ScanState::Allocating:
      return "allocating";
    case ScanState::Configuring:
      return "configuring";
    case ScanState::Online:
      return "online";
    case ScanState::Fault:
      return "fault";
  }
  return "?";
}

Scanner::Scanner(const ScannerConfig& cfg, can::Bus* bus) : cfg_(cfg), bus_(bus) {
  by_mac_.fill(-1);
}

std::size_t Scanner::add(const ScanEntry& e) {
  auto d = std::make_unique<Device>();
  d->cfg = e;
  d->in.assign(e.input_size, 0);
  d->out.assign(e.output_size, 0);
  d->poll_rx.set_expected(e.input_size);
  by_mac_[e.mac & 0x3F] = static_cast<std::int16_t>(devices_.size());
  devices_.push_back(std::move(d));
  return devices_.size() - 1;
}

void Scanner::tick(TIME now) {
  can::Frame f;
  for (int n = 0; n < 4096 && bus_->receive(f); ++n) on_frame(f, now);

  if (phase_ == Phase::Start) {
    phase_ = Phase::DupMacCheck;
    dup_next_ = now;
  }
  if (phase_ == Phase::DupMacCheck && now >= dup_next_) {
    if (dup_sent_ == 2) {
      phase_ = Phase::Online;
      next_poll_ = now;
      for (auto& d : devices_) d->next_try = now;
    } else {
      bus_->send(build_dup_mac(cfg_.mac, {false, 0, cfg_.vendor, cfg_.serial}));
      ++dup_sent_;
      dup_next_ = now + cfg_.dup_mac_wait;
    }
  }
  if (phase_ != Phase::Online) return;

  const bool bus_off = bus_->state() == can::BusState::BusOff;
  for (auto& d : devices_) {
    if (bus_off) {
      if (d->state != ScanState::Waiting) lose(*d, now, "bus-off");
      d->next_try = now + cfg_.retry;
      continue;
    }
    run_device(*d, now);
  }
  if (!bus_off && now >= next_poll_) {
    for (auto& d : devices_)
      if (d->state == ScanState::Online) send_poll(*d);
    next_poll_ += cfg_.poll_cycle;
    if (next_poll_ <= now) next_poll_ = now + cfg_.poll_cycle;  // late: no burst of polls
  }
}

void Scanner::send_poll(Device& d) {
  IoFrames frames;
  if (!build_io(group2_id(d.cfg.mac, kG2Poll), d.out, frames)) return;
  for (std::size_t i = 0; i < frames.count; ++i) send(d, frames.frames[i]);
  ++d.counters.polls;
}

void Scanner::on_frame(const can::Frame& f, TIME now) {
  if (f.error() || f.extended() || f.remote()) return;  // error frames: state() tracks them
  const auto id = decode_id(f.id);
  if (!id) {
    ++bad_frames_;
    return;
  }
  if (id->group == 2 && id->msg == kG2DupMac && id->mac == cfg_.mac) {
    const auto m = parse_dup_mac(f);
    if (!m) {
      ++bad_frames_;
      return;
    }
    if (!m->response && m->vendor == cfg_.vendor && m->serial == cfg_.serial) return;  // echo
    if (phase_ == Phase::DupMacCheck) {
      phase_ = Phase::Duplicate;
      for (auto& d : devices_) {
        d->state = ScanState::Fault;
        d->last_error = "duplicate MAC ID of the master";
        d->link.set_state(io::DeviceState::Fault);
      }
    } else if (phase_ == Phase::Online && !m->response) {
      bus_->send(build_dup_mac(cfg_.mac, {true, 0, cfg_.vendor, cfg_.serial}));
    }
    return;
  }
  const std::int16_t idx = by_mac_[id->mac];
  if (idx < 0) return;  // a node we do not scan
  Device& d = *devices_[static_cast<std::size_t>(idx)];
  if (id->group == 2 && id->msg == kG2ExplicitResponse) {
    on_explicit_response(d, f, now);
  } else if (id->group == 1 && id->msg == kG1PollResponse) {
    on_poll_response(d, f, now);
  }
}

void Scanner::on_poll_response(Device& d, const can::Frame& f, TIME now) {
  if (d.state != ScanState::Online) return;
  const auto r = d.poll_rx.take(f);
  if (r == IoReassembler::Result::Bad) {
    ++d.counters.bad_frames;
    return;
  }
  if (r != IoReassembler::Result::Complete) return;
  const auto data = d.poll_rx.data();
  if (data.size() != d.in.size()) {
    // Never reaches an FB as data; the device is lost if it keeps this up.
    ++d.counters.wrong_size;
    d.last_error = "poll response of " + std::to_string(data.size()) + " bytes, expected " +
                   std::to_string(d.in.size());
    return;
  }
  std::copy(data.begin(), data.end(), d.in.begin());
  d.last_response = now;
  ++d.counters.responses;
  // An earlier bad response is history now: a later loss is a timeout of
  // its own and must not be reported as that frame (clear() keeps the
  // string's storage: no allocation on the bus thread).
  d.last_error.clear();
}

void Scanner::on_explicit_response(Device& d, const can::Frame& f, TIME now) {
  const auto r = d.rx.take(f);
  const std::uint16_t req_id = group2_id(d.cfg.mac, kG2ExplicitRequest);
  switch (r) {
    case ExplicitReassembler::Result::Ignored:
      return;
    case ExplicitReassembler::Result::Bad:
      ++d.counters.bad_frames;
      return;
    case ExplicitReassembler::Result::AckReceived:
      if (d.step != Step::None && d.tx_next > 0 && d.tx_next < d.tx.count &&
          d.rx.ack_count() == d.tx_next - 1) {
        if (d.rx.ack_status() != kAckSuccess) {
          // The slave cannot take a message this long.
          if (d.record) fail_record(d, io::RecordError::InvalidLength);
          d.step = Step::None;
          return;
        }
        send(d, d.tx.frames[d.tx_next++]);
      }
      return;
    case ExplicitReassembler::Result::FragmentAck:
      send(d, explicit_ack(req_id, cfg_.mac, false, d.rx.ack_count(), kAckSuccess));
      return;
    case ExplicitReassembler::Result::LastFragment:
      send(d, explicit_ack(req_id, cfg_.mac, false, d.rx.ack_count(), kAckSuccess));
      break;
    case ExplicitReassembler::Result::Message:
      break;
  }
  if (d.rx.header_mac() != cfg_.mac) return;  // an answer to another master
  if (d.step == Step::None) {
    ++d.counters.bad_frames;  // unsolicited, or after its timeout
    return;
  }
  on_message(d, d.rx.message(), now);
}

namespace {
std::uint16_t u16(std::span<const std::uint8_t> b, std::size_t at) {
  return b.size() >= at + 2 ? static_cast<std::uint16_t>(b[at] | (b[at + 1] << 8)) : 0;
}
}  // namespace

void Scanner::on_message(Device& d, std::span<const std::uint8_t> msg, TIME now) {
  if (msg.empty() || !(msg[0] & kResponseBit)) {
    ++d.counters.bad_frames;
    return;
  }
  const bool error = msg[0] == (em::kErrorResponse | kResponseBit);
  const std::uint8_t general = error && msg.size() > 1 ? msg[1] : 0;
  const std::uint8_t additional = error && msg.size() > 2 ? msg[2] : em::kNoAdditionalCode;
  const auto body = msg.subspan(1);
  const Step s = d.step;
  d.step = Step::None;
  d.last_explicit = now;
  auto fault = [&](const std::string& why) {
    d.state = ScanState::Fault;
    d.last_error = why;
    d.link.set_state(io::DeviceState::Fault);
    d.next_try = now + cfg_.retry;
    ++d.counters.allocation_errors;
    changed(d);
  };
  char gs[48];
  std::snprintf(gs, sizeof gs, "error response 0x%02X/0x%02X", general, additional);
  switch (s) {
    case Step::None:
      return;
    case Step::Release:
      // Success or "not allocated": either way the slave is free for us now.
      return allocate(d, now);
    case Step::Allocate:
      if (error) {
        d.state = ScanState::Waiting;
        d.last_error = std::string("allocation refused: ") + gs;
        d.next_try = now + cfg_.retry;
        ++d.counters.allocation_errors;
        return;
      }
      ++d.counters.allocations;
      d.state = ScanState::Configuring;
      d.startup_index = 0;
      d.step = Step::Release;  // "previous step" marker for next_config_step
      next_config_step(d, now);
      return;
    case Step::Vendor:
      if (error) return fault(std::string("vendor check: ") + gs);
      if (u16(body, 0) != *d.cfg.vendor)
        return fault("vendor ID " + std::to_string(u16(body, 0)) + ", expected " +
                     std::to_string(*d.cfg.vendor));
      d.step = s;
      return next_config_step(d, now);
    case Step::Product:
      if (error) return fault(std::string("product check: ") + gs);
      if (u16(body, 0) != *d.cfg.product)
        return fault("product code " + std::to_string(u16(body, 0)) + ", expected " +
                     std::to_string(*d.cfg.product));
      d.step = s;
      return next_config_step(d, now);
    case Step::Produced:
      if (error) return fault(std::string("produced size: ") + gs);
      if (u16(body, 0) != d.cfg.input_size)
        return fault("slave produces " + std::to_string(u16(body, 0)) + " bytes, configured " +
                     std::to_string(d.cfg.input_size));
      d.step = s;
      return next_config_step(d, now);
    case Step::Consumed:
      if (error) return fault(std::string("consumed size: ") + gs);
      if (u16(body, 0) != d.cfg.output_size)
        return fault("slave consumes " + std::to_string(u16(body, 0)) + " bytes, configured " +
                     std::to_string(d.cfg.output_size));
      d.step = s;
      return next_config_step(d, now);
    case Step::Epr:
      if (error) return fault(std::string("setting the expected packet rate: ") + gs);
      d.step = s;
      return next_config_step(d, now);
    case Step::Startup:
      if (error) {
        const AttributeWrite& w = d.cfg.startup[d.startup_index];
        char what[64];
        std::snprintf(what, sizeof what, "start-up write 0x%02X/%u/%u: ", w.cls, w.instance,
                      w.attribute);
        return fault(what + std::string(gs));
      }
      ++d.startup_index;
      d.step = s;
      return next_config_step(d, now);
    case Step::KeepAlive:
      return;
    case Step::Record: {
      io::RecordRequest* r = d.record;
      d.record = nullptr;
      if (!r) return;
      if (error) {
        ++d.counters.explicit_errors;
        r->fail(io::RecordError::InvalidIndex, em::error_code(general, additional));
        return;
      }
      if (body.size() > r->buffer().size()) {
        ++d.counters.explicit_errors;
        r->fail(io::RecordError::InvalidLength);
        return;
      }
      std::copy(body.begin(), body.end(), r->buffer().begin());
      ++d.counters.explicit_ok;
      r->complete(body.size());
      return;
    }
  }
}

// Configuring: the next check or write after d.step (the one just done).
void Scanner::next_config_step(Device& d, TIME now) {
  const Step done = d.step;
  d.step = Step::None;
  auto get = [&](Step s, std::uint8_t cls, std::uint8_t inst, std::uint8_t attr) {
    const std::uint8_t m[] = {em::kGetAttributeSingle, cls, inst, attr};
    begin(d, s, m, false, now);
  };
  switch (done) {
    case Step::Release:
      if (d.cfg.vendor) return get(Step::Vendor, kClassIdentity, 1, 1);
      [[fallthrough]];
    case Step::Vendor:
      if (d.cfg.product) return get(Step::Product, kClassIdentity, 1, 3);
      [[fallthrough]];
    case Step::Product:
      return get(Step::Produced, kClassConnection, kConnPoll, kConnAttrProducedSize);
    case Step::Produced:
      return get(Step::Consumed, kClassConnection, kConnPoll, kConnAttrConsumedSize);
    case Step::Consumed: {
      const auto epr_ms = static_cast<std::uint16_t>(
          std::chrono::duration_cast<std::chrono::milliseconds>(d.cfg.epr).count());
      const std::uint8_t m[] = {em::kSetAttributeSingle,
                                kClassConnection,
                                kConnPoll,
                                kConnAttrEpr,
                                static_cast<std::uint8_t>(epr_ms),
                                static_cast<std::uint8_t>(epr_ms >> 8)};
      return begin(d, Step::Epr, m, false, now);
    }
    case Step::Epr:
    case Step::Startup:
      if (d.startup_index < d.cfg.startup.size()) {
        const AttributeWrite& w = d.cfg.startup[d.startup_index];
        std::array<std::uint8_t, kMaxExplicitMessage> m{};
        const std::size_t n =
            em::encode_request(em::kSetAttributeSingle, {w.cls, w.instance, w.attribute}, w.data,
                               std::span(m).subspan(1));
        m[0] = em::kSetAttributeSingle;
        return begin(d, Step::Startup, {m.data(), n + 1}, false, now);
      }
      d.state = ScanState::Online;
      d.last_response = now;  // the connection timeout runs from here
      d.last_error.clear();
      d.link.set_state(io::DeviceState::Online);
      changed(d);
      send_poll(d);
      return;
    default:
      return;
  }
}

void Scanner::begin(Device& d, Step s, std::span<const std::uint8_t> msg, bool unconnected,
                    TIME now) {
  const std::uint16_t id = group2_id(d.cfg.mac, unconnected ? kG2Unconnected : kG2ExplicitRequest);
  d.rx.reset();
  if (!build_explicit(id, cfg_.mac, false, msg, d.tx)) {
    if (d.record) fail_record(d, io::RecordError::InvalidLength);
    return;
  }
  d.step = s;
  d.deadline = now + cfg_.explicit_timeout;
  d.last_explicit = now;
  d.tx_next = 1;
  if (send(d, d.tx.frames[0]) || (s != Step::Release && s != Step::Allocate)) return;
  // A Release or an Allocate the interface did not take never reached the
  // slave: it is sent again after `retry`, not waited out. A Release waited
  // out is followed by an Allocate that a slave still allocated to us
  // refuses (0x0B, already in the requested mode), a lost retry more.
  d.step = Step::None;
  d.state = ScanState::Waiting;
  d.last_error = s == Step::Release ? "Release not sent (the interface took no frame)"
                                    : "Allocate not sent (the interface took no frame)";
  d.next_try = now + cfg_.retry;
}

bool Scanner::send(Device& d, const can::Frame& f) {
  if (bus_->send(f)) return true;
  ++d.counters.send_failures;
  return false;
}

void Scanner::allocate(Device& d, TIME now) {
  const std::uint8_t m[] = {em::kAllocateMasterSlave, kClassDeviceNet, 1,
                            kAllocExplicit | kAllocPoll, cfg_.mac};
  d.state = ScanState::Allocating;
  begin(d, Step::Allocate, m, true, now);
}

void Scanner::fail_record(Device& d, io::RecordError e, std::uint16_t code) {
  if (d.record) {
    if (e == io::RecordError::Timeout)
      ++d.counters.explicit_timeouts;
    else
      ++d.counters.explicit_errors;
    d.record->fail(e, code);
  }
  d.record = nullptr;
}

void Scanner::changed(const Device& d) {
  if (!on_change) return;
  for (std::size_t i = 0; i < devices_.size(); ++i)
    if (devices_[i].get() == &d) on_change(i, d.state, d.last_error);
}

void Scanner::lose(Device& d, TIME now, const std::string& why) {
  const bool was_online = d.state == ScanState::Online;
  if (was_online) ++d.counters.losses;
  d.state = ScanState::Waiting;
  d.last_error = why;
  d.step = Step::None;
  fail_record(d, io::RecordError::NotReachable);
  for (io::RecordRequest* r = d.link.pop(); r; r = d.link.pop())
    r->fail(io::RecordError::NotReachable);
  std::fill(d.in.begin(), d.in.end(), 0);  // invalid inputs never look like data
  d.link.set_state(io::DeviceState::Offline);
  d.poll_rx.reset();
  d.next_try = now + cfg_.retry;
  if (was_online) changed(d);
}

void Scanner::run_device(Device& d, TIME now) {
  // A transaction without an answer in time.
  if (d.step != Step::None && now >= d.deadline) {
    const Step s = d.step;
    d.step = Step::None;
    if (s == Step::Record) {
      fail_record(d, io::RecordError::Timeout);
    } else if (s == Step::Release) {
      // A slave that does not answer Release (already free, or a strict
      // one) may still take Allocate.
      return allocate(d, now);
    } else if (s != Step::KeepAlive) {
      lose(d, now, s == Step::Allocate ? "no answer to Allocate" : "no answer while configuring");
      return;
    }
  }
  switch (d.state) {
    case ScanState::Waiting:
    case ScanState::Fault:
      if (now >= d.next_try) {
        d.state = ScanState::Releasing;
        const std::uint8_t m[] = {em::kReleaseMasterSlave, kClassDeviceNet, 1,
                                  kAllocExplicit | kAllocPoll};
        begin(d, Step::Release, m, true, now);
      }
      return;
    case ScanState::Online:
      break;
    default:
      return;
  }
  if (now - d.last_response > kTimeoutMultiplier * d.cfg.epr) {
    const auto silent_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(now - d.last_response).count();
    lose(d, now,
         (d.last_error.empty() ? std::string("connection timed out") : d.last_error) +
             " (no valid poll response for " + std::to_string(silent_ms) + " ms, timeout " +
             std::to_string(
                 kTimeoutMultiplier *
                 std::chrono::duration_cast<std::chrono::milliseconds>(d.cfg.epr).count()) +
             " ms)");
    return;
  }
  if (d.step != Step::None) return;
  if (io::RecordRequest* r = d.link.pop()) {
    const auto req = r->kind() == io::RecordKind::Read ? em::decode_request(r->index(), r->data())
                                                       : std::nullopt;
    if (!req) {
      r->fail(io::RecordError::InvalidIndex);
      ++d.counters.explicit_errors;
      return;
    }
    std::array<std::uint8_t, kMaxExplicitMessage> m{};
    m[0] = req->service;
    const auto in = r->data();
    if (in.size() + 1 > m.size()) {
      r->fail(io::RecordError::InvalidLength);
      return;
    }
    std::copy(in.begin(), in.end(), m.begin() + 1);
    d.record = r;
    begin(d, Step::Record, {m.data(), in.size() + 1}, false, now);
    return;
  }
  if (now - d.last_explicit >= cfg_.keep_alive) {
    const std::uint8_t m[] = {em::kGetAttributeSingle, kClassIdentity, 1, 5};
    begin(d, Step::KeepAlive, m, false, now);
  }
}

std::string Scanner::diagnostics(std::size_t i) const {
  const Device& d = *devices_[i];
  const DeviceCounters& c = d.counters;
  char b[512];
  std::snprintf(
      b, sizeof b,
      "devicenet mac %u %s; polls %llu responses %llu losses %llu allocations %llu "
      "(refused %llu) bad-frames %llu wrong-size %llu explicit ok %llu err %llu "
      "timeout %llu send-failed %llu%s%s",
      d.cfg.mac, to_string(d.state), static_cast<unsigned long long>(c.polls),
      static_cast<unsigned long long>(c.responses), static_cast<unsigned long long>(c.losses),
      static_cast<unsigned long long>(c.allocations),
      static_cast<unsigned long long>(c.allocation_errors),
      static_cast<unsigned long long>(c.bad_frames), static_cast<unsigned long long>(c.wrong_size),
      static_cast<unsigned long long>(c.explicit_ok),
      static_cast<unsigned long long>(c.explicit_errors),
      static_cast<unsigned long long>(c.explicit_timeouts),
      static_cast<unsigned long long>(c.send_failures),
      d.last_error.empty() ? "" : "; last: ", d.last_error.c_str());
  return b;
}

}  // namespace plc::devicenet
