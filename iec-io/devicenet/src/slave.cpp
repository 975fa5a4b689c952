#include "plc/devicenet/slave.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "plc/devicenet/identifiers.hpp"
#include "plc/devicenet/objects.hpp"
#include "plc/io/explicit_message.hpp"

namespace plc::devicenet {

namespace em = io::explicit_msg;

namespace {

TIME ms(std::uint16_t v) { return std::chrono::milliseconds(v); }

std::size_t error_response(std::span<std::uint8_t> resp, std::uint8_t general,
                           std::uint8_t additional = em::kNoAdditionalCode) {
  resp[0] = em::kErrorResponse | kResponseBit;
  resp[1] = general;
  resp[2] = additional;
  return 3;
}

std::size_t ok(std::span<std::uint8_t> resp, std::uint8_t service) {
  resp[0] = static_cast<std::uint8_t>(service | kResponseBit);
  return 1;
}

std::size_t put_u16(std::span<std::uint8_t> resp, std::uint8_t service, std::uint16_t v) {
  ok(resp, service);
  resp[1] = static_cast<std::uint8_t>(v);
  resp[2] = static_cast<std::uint8_t>(v >> 8);
  return 3;
}

std::size_t put_u8(std::span<std::uint8_t> resp, std::uint8_t service, std::uint8_t v) {
  ok(resp, service);
  resp[1] = v;
  return 2;
}

// The general status for a model's refusal: device codes (>= 0x100) carry
// general << 8 | additional already (explicit_message.hpp); the transport
// codes map to their nearest §11.1 meaning.
std::pair<std::uint8_t, std::uint8_t> general_of(io::RecordError e) {
  const auto code = static_cast<std::uint16_t>(e);
  if (code >= 0x100) return {em::general_status(code), em::additional_code(code)};
  switch (e) {
    case io::RecordError::InvalidIndex:
      return {em::kObjectDoesNotExist, em::kNoAdditionalCode};
    case io::RecordError::InvalidLength:
      return {em::kReplyDataTooLarge, em::kNoAdditionalCode};
    case io::RecordError::DeviceBusy:
      return {em::kResourceUnavailable, em::kNoAdditionalCode};
    case io::RecordError::InvalidState:
      return {em::kDeviceStateConflict, em::kNoAdditionalCode};
    default:
      return {em::kVendorSpecific, static_cast<std::uint8_t>(code)};
  }
}

}  // namespace

Slave::Slave(const SlaveConfig& cfg, std::unique_ptr<io::DeviceModel> model, can::Bus& bus)
    : cfg_(cfg), model_(std::move(model)), bus_(bus) {
  inputs_.assign(model_->input_size(), 0);
  outputs_.assign(model_->output_size(), 0);
  poll_rx_.set_expected(outputs_.size());
}

void Slave::tick(TIME now) {
  if (!started_) {
    started_ = true;
    last_tick_ = now;
    dup_next_ = now;
  }
  if (phase_ == Phase::DupMacCheck && now >= dup_next_ && !faults_.silent) {
    if (dup_sent_ == 2) {
      phase_ = Phase::Online;
    } else {
      bus_.send(build_dup_mac(cfg_.mac, {false, 0, cfg_.identity.vendor, cfg_.identity.serial}));
      ++dup_sent_;
      dup_next_ = now + cfg_.dup_mac_wait;
    }
  }
  can::Frame f;
  for (int n = 0; n < 4096 && bus_.receive(f); ++n) {
    if (faults_.silent) continue;  // unplugged: hears nothing, says nothing
    on_frame(f, now);
  }
  watchdogs(now);
  const TIME dt = now - last_tick_;
  last_tick_ = now;
  model_->step_io(now, dt, outputs_, outputs_new_, inputs_);
  outputs_new_ = false;
}

void Slave::deliver_outputs(TIME now) {
  if (!outputs_new_) return;
  model_->step_io(now, TIME{0}, outputs_, true, inputs_);
  outputs_new_ = false;
}

void Slave::on_frame(const can::Frame& f, TIME now) {
  if (f.error() || f.extended() || f.remote()) return;
  const auto id = decode_id(f.id);
  if (!id || id->group != 2 || id->mac != cfg_.mac) return;
  switch (id->msg) {
    case kG2DupMac:
      on_dup_mac(f);
      break;
    case kG2Unconnected:
      if (phase_ == Phase::Online) on_explicit(f, true, now);
      break;
    case kG2ExplicitRequest:
      if (phase_ == Phase::Online && (choice_ & kAllocExplicit)) on_explicit(f, false, now);
      break;
    case kG2Poll:
      if (phase_ == Phase::Online && (choice_ & kAllocPoll)) on_poll(f, now);
      break;
    default:
      break;  // our own responses (echo) and services we do not offer
  }
}

void Slave::on_dup_mac(const can::Frame& f) {
  const auto m = parse_dup_mac(f);
  if (!m) {
    ++counters_.bad_frames;
    return;
  }
  if (!m->response && m->vendor == cfg_.identity.vendor && m->serial == cfg_.identity.serial)
    return;  // our own request, echoed by the bus
  if (phase_ == Phase::DupMacCheck) {
    phase_ = Phase::DuplicateFound;  // another node has our MAC: stay off the bus
  } else if (phase_ == Phase::Online && !m->response) {
    bus_.send(build_dup_mac(cfg_.mac, {true, 0, cfg_.identity.vendor, cfg_.identity.serial}));
  }
}

void Slave::on_explicit(const can::Frame& f, bool unconnected, TIME now) {
  const auto r = rx_.take(f);
  const std::uint16_t resp_id = group2_id(cfg_.mac, kG2ExplicitResponse);
  switch (r) {
    case ExplicitReassembler::Result::Ignored:
      return;
    case ExplicitReassembler::Result::Bad:
      ++counters_.bad_frames;
      return;
    case ExplicitReassembler::Result::AckReceived:
      if (tx_next_ > 0 && tx_next_ < tx_.count && rx_.ack_count() == tx_next_ - 1 &&
          rx_.ack_status() == kAckSuccess) {
        bus_.send(tx_.frames[tx_next_++]);
      }
      return;
    case ExplicitReassembler::Result::FragmentAck:
      bus_.send(explicit_ack(resp_id, master_, false, rx_.ack_count(), kAckSuccess));
      explicit_last_ = now;
      return;
    case ExplicitReassembler::Result::LastFragment:
      bus_.send(explicit_ack(resp_id, master_, false, rx_.ack_count(), kAckSuccess));
      break;
    case ExplicitReassembler::Result::Message:
      break;
  }
  // Requests on the explicit connection come from its master only.
  if (!unconnected && rx_.header_mac() != master_) {
    ++counters_.bad_frames;
    return;
  }
  explicit_last_ = now;
  ++counters_.explicit_requests;
  std::array<std::uint8_t, kMaxExplicitMessage> resp{};
  const std::size_t n = serve(rx_.message(), unconnected, resp, now);
  if (n) send_response({resp.data(), n});
  if (reset_pending_) {
    // Identity Reset: the answer first, then the device starts over as
    // after a power cycle (connections gone; the master re-allocates).
    reset_pending_ = false;
    release(0xFF);
    outputs_new_ = false;  // a poll of this tick was for the device before its reset
    model_->power_cycle();
  }
}

void Slave::send_response(std::span<const std::uint8_t> msg) {
  // The header names the client that asked (toyo-vf66-devicenet.md §1.4
  // [std]: the master's MAC ID in both directions): on the explicit
  // connection that is our master, on the unconnected port anyone, e.g. a
  // second master whose Allocate we refuse; that refusal addressed to our
  // own master would read to it as an answer to its own request.
  if (!build_explicit(group2_id(cfg_.mac, kG2ExplicitResponse), rx_.header_mac(), false, msg, tx_))
    return;
  bus_.send(tx_.frames[0]);
  tx_next_ = 1;
}

std::size_t Slave::serve(std::span<const std::uint8_t> msg, bool unconnected,
                         std::span<std::uint8_t> resp, TIME now) {
  if (msg.size() < 3 || (msg[0] & kResponseBit)) {
    ++counters_.bad_frames;
    return msg.empty() || (msg[0] & kResponseBit) ? 0 : error_response(resp, em::kNotEnoughData);
  }
  const std::uint8_t service = msg[0];
  const std::uint8_t cls = msg[1], inst = msg[2];
  if (cls == kClassDeviceNet && inst == 1 && service == em::kAllocateMasterSlave)
    return serve_allocate(msg, resp, now);
  if (cls == kClassDeviceNet && inst == 1 && service == em::kReleaseMasterSlave)
    return serve_release(msg, resp);
  if (unconnected) return 0;  // the unconnected port serves allocation only
  return serve_object(service, cls, inst, msg.subspan(3), resp, now);
}

std::size_t Slave::serve_allocate(std::span<const std::uint8_t> msg, std::span<std::uint8_t> resp,
                                  TIME now) {
  const std::uint8_t svc = em::kAllocateMasterSlave;
  if (msg.size() < 5) return error_response(resp, em::kNotEnoughData);
  if (msg.size() > 5) return error_response(resp, em::kTooMuchData);
  const std::uint8_t choice = msg[3], mac = msg[4] & 0x3F;
  if (faults_.refuse_allocation) return error_response(resp, em::kResourceUnavailable);
  if (master_ != kUnallocated && master_ != mac)
    return error_response(resp, em::kObjectStateConflict, 0x01);
  // Poll and explicit only (§1.3 [inf]: the assemblies fit polled I/O).
  if (choice & ~(kAllocExplicit | kAllocPoll))
    return error_response(resp, em::kResourceUnavailable, 0x02);
  if (choice == 0 || (choice_ & choice)) return error_response(resp, em::kAlreadyInState);
  master_ = mac;
  choice_ |= choice | kAllocExplicit;  // allocating anything brings the explicit connection
  explicit_epr_ms_ = kDefaultExplicitEprMs;
  explicit_last_ = now;
  if (choice & kAllocPoll) {
    poll_state_ = kConnConfiguring;  // until the master sets the EPR (§12 [std])
    poll_epr_ms_ = 0;
    poll_rx_.reset();
  }
  ++counters_.allocations;
  ok(resp, svc);
  resp[1] = 0;  // message body format 8/8
  return 2;
}

std::size_t Slave::serve_release(std::span<const std::uint8_t> msg, std::span<std::uint8_t> resp) {
  if (msg.size() < 4) return error_response(resp, em::kNotEnoughData);
  const std::uint8_t choice = msg[3];
  if (master_ == kUnallocated || (choice_ & choice) == 0)
    return error_response(resp, em::kAlreadyInState);
  release(choice);
  return ok(resp, em::kReleaseMasterSlave);
}

void Slave::release(std::uint8_t choice) {
  if (choice & kAllocPoll) {
    poll_state_ = kConnNonExistent;
    poll_epr_ms_ = 0;
  }
  choice_ &= static_cast<std::uint8_t>(~choice);
  if (!(choice_ & kAllocExplicit)) choice_ = 0;  // without the explicit connection nothing stays
  if (choice_ == 0) {
    master_ = kUnallocated;
    poll_state_ = kConnNonExistent;
  }
}

std::size_t Slave::serve_object(std::uint8_t service, std::uint8_t cls, std::uint8_t inst,
                                std::span<const std::uint8_t> body, std::span<std::uint8_t> resp,
                                TIME now) {
  const bool get = service == em::kGetAttributeSingle;
  const bool set = service == em::kSetAttributeSingle;
  const bool attr_service = get || set;
  if (attr_service && body.empty()) return error_response(resp, em::kNotEnoughData);
  const std::uint8_t attr = attr_service ? body[0] : 0;
  const auto data = attr_service ? body.subspan(1) : body;
  const SlaveIdentity& id = cfg_.identity;

  switch (cls) {
    case kClassIdentity: {
      if (inst != 1) return error_response(resp, em::kObjectDoesNotExist);
      if (service == em::kReset) {
        if (!data.empty() && data[0] > 1) return error_response(resp, em::kInvalidParameter);
        reset_pending_ = true;
        return ok(resp, service);
      }
      if (set) return error_response(resp, em::kAttributeNotSettable);
      if (!get) return error_response(resp, em::kServiceNotSupported);
      switch (attr) {
        case 1:
          return put_u16(resp, service, id.vendor);
        case 2:
          return put_u16(resp, service, id.device_type);
        case 3:
          return put_u16(resp, service, id.product_code);
        case 4:
          ok(resp, service);
          resp[1] = id.major_rev;
          resp[2] = id.minor_rev;
          return 3;
        case 5:
          return put_u16(resp, service, master_ != kUnallocated ? 0x0001 : 0x0000);  // owned
        case 6:
          ok(resp, service);
          for (int i = 0; i < 4; ++i) resp[1 + i] = static_cast<std::uint8_t>(id.serial >> (8 * i));
          return 5;
        case 7: {
          ok(resp, service);
          const std::size_t n = std::min<std::size_t>(id.product_name.size(), 32);
          resp[1] = static_cast<std::uint8_t>(n);  // SHORT_STRING
          std::copy_n(id.product_name.begin(), n, resp.begin() + 2);
          return 2 + n;
        }
        default:
          return error_response(resp, em::kAttributeNotSupported);
      }
    }
    case kClassDeviceNet: {
      if (inst != 1) return error_response(resp, em::kObjectDoesNotExist);
      if (set) return error_response(resp, em::kAttributeNotSettable);
      if (!get) return error_response(resp, em::kServiceNotSupported);
      switch (attr) {
        case 1:
          return put_u8(resp, service, cfg_.mac);
        case 2:
          return put_u8(resp, service, cfg_.baud_code);
        case 3:
          return put_u8(resp, service, 0);  // BOI: hold in bus-off
        case 4:
          return put_u8(resp, service, 0);
        case 5:
          ok(resp, service);
          resp[1] = choice_;
          resp[2] = master_;
          return 3;
        default:
          return error_response(resp, em::kAttributeNotSupported);
      }
    }
    case kClassAssembly: {
      const bool is_in = inst == cfg_.input_assembly, is_out = inst == cfg_.output_assembly;
      if (!is_in && !is_out) return error_response(resp, em::kObjectDoesNotExist);
      if (!attr_service) return error_response(resp, em::kServiceNotSupported);
      if (attr != 3) return error_response(resp, em::kAttributeNotSupported);
      std::vector<std::uint8_t>& buf = is_in ? inputs_ : outputs_;
      if (get) {
        if (buf.size() + 1 > resp.size()) return error_response(resp, em::kReplyDataTooLarge);
        ok(resp, service);
        std::copy(buf.begin(), buf.end(), resp.begin() + 1);
        return 1 + buf.size();
      }
      if (is_in) return error_response(resp, em::kAttributeNotSettable);
      if (poll_state_ == kConnEstablished) return error_response(resp, em::kObjectStateConflict);
      if (data.size() < buf.size()) return error_response(resp, em::kNotEnoughData);
      if (data.size() > buf.size()) return error_response(resp, em::kTooMuchData);
      std::copy(data.begin(), data.end(), buf.begin());
      outputs_new_ = true;
      return ok(resp, service);
    }
    case kClassConnection: {
      if (inst != kConnExplicit && inst != kConnPoll)
        return error_response(resp, em::kObjectDoesNotExist);
      const bool poll = inst == kConnPoll;
      if (poll && !(choice_ & kAllocPoll)) return error_response(resp, em::kObjectDoesNotExist);
      if (!attr_service) return error_response(resp, em::kServiceNotSupported);
      const std::uint16_t produced = poll ? static_cast<std::uint16_t>(inputs_.size()) : 256;
      const std::uint16_t consumed = poll ? static_cast<std::uint16_t>(outputs_.size()) : 256;
      if (set) {
        if (attr != kConnAttrEpr) {
          return attr == kConnAttrState || attr == kConnAttrProducedSize ||
                         attr == kConnAttrConsumedSize || attr == kConnAttrWatchdogAction
                     ? error_response(resp, em::kAttributeNotSettable)
                     : error_response(resp, em::kAttributeNotSupported);
        }
        if (data.size() < 2) return error_response(resp, em::kNotEnoughData);
        if (data.size() > 2) return error_response(resp, em::kTooMuchData);
        // EPR is kept in ms; CIP rounds it up to the device's timer tick (1 ms
        // here), so the value read back is the one written.
        const std::uint16_t epr = static_cast<std::uint16_t>(data[0] | (data[1] << 8));
        if (poll) {
          poll_epr_ms_ = epr;
          poll_state_ = kConnEstablished;
          poll_last_ = now;
        } else {
          explicit_epr_ms_ = epr;
        }
        return put_u16(resp, service, epr);
      }
      switch (attr) {
        case kConnAttrState:
          return put_u8(resp, service, poll ? poll_state_ : kConnEstablished);
        case kConnAttrProducedSize:
          return put_u16(resp, service, produced);
        case kConnAttrConsumedSize:
          return put_u16(resp, service, consumed);
        case kConnAttrEpr:
          return put_u16(resp, service, poll ? poll_epr_ms_ : explicit_epr_ms_);
        case kConnAttrWatchdogAction:
          return put_u8(resp, service, poll ? 0 : 1);  // timed out / auto delete
        default:
          return error_response(resp, em::kAttributeNotSupported);
      }
    }
    default:
      break;
  }
  // Every other object belongs to the model (explicit_message.hpp mapping).
  deliver_outputs(now);
  std::array<std::uint8_t, kMaxExplicitMessage> req{};
  if (body.size() + 2 > req.size()) return error_response(resp, em::kTooMuchData);
  req[0] = cls;
  req[1] = inst;
  std::copy(body.begin(), body.end(), req.begin() + 2);
  std::size_t len = 0;
  const io::RecordError e = model_->query_record(
      em::record_index(service), {req.data(), body.size() + 2}, resp.subspan(1), len);
  if (e != io::RecordError::None) {
    const auto [g, a] = general_of(e);
    return error_response(resp, g, a);
  }
  ok(resp, service);
  return 1 + std::min(len, resp.size() - 1);
}

void Slave::on_poll(const can::Frame& f, TIME now) {
  // Timed Out stays so until the master releases and allocates again (the
  // watchdog action "transition to timed out", §12 [std]).
  if (poll_state_ != kConnEstablished) return;
  const auto r = poll_rx_.take(f);
  if (r == IoReassembler::Result::Bad) {
    ++counters_.bad_frames;
    return;
  }
  if (r != IoReassembler::Result::Complete) return;
  const auto data = poll_rx_.data();
  if (data.size() > outputs_.size()) {
    ++counters_.wrong_size_polls;  // longer: ignored, and we stop producing (§2 fieldbus-masters)
    return;
  }
  poll_last_ = now;
  ++counters_.polls;
  if (data.size() == outputs_.size()) {
    std::copy(data.begin(), data.end(), outputs_.begin());
    outputs_new_ = true;
  } else {
    ++counters_.wrong_size_polls;  // shorter: data ignored, we still produce
  }
  // Fault switch "wrong sizes": answer with a length the master did not configure.
  std::vector<std::uint8_t> produced(inputs_);
  if (faults_.size_error > 0) produced.resize(produced.size() + std::size_t(faults_.size_error), 0);
  if (faults_.size_error < 0)
    produced.resize(produced.size() - std::min(produced.size(), std::size_t(-faults_.size_error)));
  IoFrames frames;
  if (!build_io(group1_id(kG1PollResponse, cfg_.mac), produced, frames)) return;
  for (std::size_t i = 0; i < frames.count; ++i) bus_.send(frames.frames[i]);
}

void Slave::watchdogs(TIME now) {
  if (poll_state_ == kConnEstablished && poll_epr_ms_ > 0 &&
      now - poll_last_ > kTimeoutMultiplier * ms(poll_epr_ms_)) {
    poll_state_ = kConnTimedOut;
    ++counters_.io_timeouts;
    model_->io_connection_lost();
  }
  if ((choice_ & kAllocExplicit) && explicit_epr_ms_ > 0 &&
      now - explicit_last_ > kTimeoutMultiplier * ms(explicit_epr_ms_)) {
    // Watchdog action of the predefined explicit connection: auto delete.
    ++counters_.explicit_timeouts;
    release(kAllocExplicit);
  }
}

std::string Slave::describe() const {
  char b[256];
  const char* ph = phase_ == Phase::Online        ? "online"
                   : phase_ == Phase::DupMacCheck ? "dup-mac-check"
                                                  : "duplicate-mac";
  std::snprintf(b, sizeof b,
                "mac %u %s master %u choice 0x%02X poll-state %u epr %u ms polls %llu "
                "explicit %llu io-timeouts %llu bad %llu",
                cfg_.mac, ph, master_, choice_, poll_state_, poll_epr_ms_,
                static_cast<unsigned long long>(counters_.polls),
                static_cast<unsigned long long>(counters_.explicit_requests),
                static_cast<unsigned long long>(counters_.io_timeouts),
                static_cast<unsigned long long>(counters_.bad_frames));
  return b;
}

}  // namespace plc::devicenet
