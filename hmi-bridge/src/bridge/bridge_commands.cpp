// Commands: an LCM command_t in, after the decode guard and the shared key,
// becomes a binary record for plcrun (plc/hmi/ipc/records.hpp); plcrun's
// reply record comes back as a reply_t. Everything that reads text is here:
// names are looked up in the layout, literals parsed into the type's bytes
// (parse_value), conditions compiled into code (compile_condition).
#include <unistd.h>

#include <algorithm>
#include <cstring>

#include "bridge_view.hpp"
#include "plc/hmi/bridge.hpp"
#include "plc/hmi/checked_decode.hpp"
#include "plc/hmi/value_text.hpp"
#include "plc/iec_literal.hpp"

namespace plc::hmi {

namespace {

using ipc::Verb;
using ipc::WireOperand;

std::string bounded(const char* s, std::size_t cap) { return std::string(s, strnlen(s, cap)); }

ipc::WireOperand var_operand(std::uint32_t index) {
  ipc::WireOperand o;
  o.kind = WireOperand::Var;
  o.value = index;
  return o;
}

ipc::WireOperand address_operand(const io::IecAddress& a) {
  ipc::WireOperand o;
  o.kind = WireOperand::Address;
  o.area = std::uint8_t(a.area);
  o.size = std::uint8_t(a.size);
  o.bit = a.bit;
  o.value = a.byte;
  return o;
}

}  // namespace

void Bridge::on_command_bytes(const void* data, std::size_t size) {
  softplc_hmi::command_t c;
  if (size > 65536 || !checked_decode(data, size, c)) {
    count(&BridgeCounters::malformed);
    return;
  }
  if (auto r = handle(c)) publish_reply(std::move(*r));
}

void Bridge::publish_reply(softplc_hmi::reply_t r) {
  r.n = int(r.values.size());
  // Every reply is signed, refusals too: with a random request id (plcctl)
  // a signed reply to someone else's request answers nothing of its own.
  set_epoch(r, epoch_);
  if (key_) sign(r, *key_, tag_context(ch_.reply));
  if (in_handler_) {
    if (replies_.size() < 1000) replies_.push_back(std::move(r));
  } else {
    transport_->publish(ch_.reply, &r);
    if (tap_) tap_->on_reply(r);
  }
}

void Bridge::flush_replies() {
  std::vector<softplc_hmi::reply_t> out;
  out.swap(replies_);
  for (const auto& r : out) {
    transport_->publish(ch_.reply, &r);
    if (tap_) tap_->on_reply(r);
  }
}

bool Bridge::submit(softplc_hmi::command_t c) {
  std::lock_guard<std::mutex> lock(local_mu_);
  if (local_.size() >= kLocalInbox) return false;
  local_.push_back(std::move(c));
  return true;
}

void Bridge::serve_local() {
  std::vector<softplc_hmi::command_t> in;
  {
    std::lock_guard<std::mutex> lock(local_mu_);
    in.swap(local_);
  }
  for (const auto& c : in)
    if (auto r = handle(c, true)) publish_reply(std::move(*r));
}

std::optional<softplc_hmi::reply_t> Bridge::handle(const softplc_hmi::command_t& c, bool local) {
  softplc_hmi::reply_t r;
  r.request_id = c.request_id;
  r.client = c.client;
  auto refuse = [&](std::string why, std::uint64_t BridgeCounters::*counter) {
    r.ok = false;
    r.refusal = std::move(why);
    count(counter);
    return std::optional<softplc_hmi::reply_t>(r);
  };
  // describe changes nothing and is how a client learns the epoch it must
  // sign for: it needs no tag (what it publishes is signed). authenticate()
  // counts its refusals itself.
  if (c.verb != "describe" && !local) {
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
  if (!view_) return refuse("the cell's layout is not readable now", &BridgeCounters::refused);
  const View& view = *view_;
  ipc::CommandRecord& rec = *rec_;
  rec = ipc::CommandRecord{};
  Pending p;
  p.request_id = c.request_id;
  p.client = c.client;
  const bool stops =
      v == "pause" || v == "step" || v == "continue" || v == "break" || v == "delete";
  if (stops && !settings_.stop_commands)
    return refuse("'" + v + "' is not allowed: the cell's hmi: stop_commands is false",
                  &BridgeCounters::refused);
  // A name of the layout, or an address inside the image (read, break).
  auto operand = [&view](const std::string& name,
                         std::string& why) -> std::optional<ipc::WireOperand> {
    if (auto it = view.index.find(name); it != view.index.end()) return var_operand(it->second);
    if (!name.empty() && name[0] == '%') {
      const auto parsed = io::parse_iec_address(name);
      if (!parsed.address) {
        why = parsed.error;
        return std::nullopt;
      }
      if (!view.cell.inside_image(*parsed.address)) {
        why = name + " lies outside the image";
        return std::nullopt;
      }
      // An address the layout lists under its canonical name (%IX0.0 for %I0.0).
      if (auto it = view.index.find(parsed.address->to_string()); it != view.index.end())
        return var_operand(it->second);
      return address_operand(*parsed.address);
    }
    why = "unknown variable '" + name + "' (plcrun CONFIG --list-vars lists them)";
    return std::nullopt;
  };
  if (v == "read") {
    if (a.empty()) return refuse("read: name at least one variable", &BridgeCounters::refused);
    rec.verb = std::uint8_t(Verb::Read);
    for (const std::string& name : a) {
      std::string why;
      const auto o = operand(name, why);
      p.names.push_back(name);
      p.errors.push_back(why);
      p.operand.push_back(o ? int(rec.n_operands) : -1);
      std::string address;
      if (o && o->kind == WireOperand::Var && view.cell.vars[o->value].address)
        address = view.cell.vars[o->value].address->to_string();
      if (o && o->kind == WireOperand::Address)
        address =
            io::IecAddress{io::Area(o->area), io::AddrSize(o->size), o->value, o->bit}.to_string();
      p.addresses.push_back(address);
      if (!o) continue;
      if (rec.n_operands == ipc::kMaxReadOperands)
        return refuse(
            "read: at most " + std::to_string(ipc::kMaxReadOperands) + " variables per command",
            &BridgeCounters::refused);
      rec.operands[rec.n_operands++] = *o;
    }
    if (rec.n_operands == 0) {  // nothing plcrun needs to read
      for (std::size_t i = 0; i < p.names.size(); ++i) {
        softplc_hmi::var_value_t o;
        o.path = p.names[i];
        o.error = p.errors[i];
        r.values.push_back(o);
      }
      r.ok = true;
      count(&BridgeCounters::commands);
      return r;
    }
    p.verb = Verb::Read;
    return queue(rec, std::move(p));
  }
  if (v == "write" || v == "force") {
    if (a.size() != 2) return refuse(v + ": needs NAME VALUE", &BridgeCounters::refused);
    const auto it = view.index.find(a[0]);
    const bool write = v == "write";
    if (it == view.index.end() ||
        !(write ? view.cell.vars[it->second].writable : view.cell.vars[it->second].forceable))
      return refuse(v + " " + a[0] + ": not allowed (the cell's hmi: " +
                        (write ? "writable" : "forceable") + " patterns do not match it)",
                    &BridgeCounters::refused);
    const ipc::CellLayout::Var& var = view.cell.vars[it->second];
    // The literal, parsed here into the type's bytes: plcrun gets no text.
    alignas(8) unsigned char value[8] = {};
    const std::string err = parse_value(var.type, a[1], value);
    if (!err.empty()) return refuse(v + " " + a[0] + ": " + err + "\n", &BridgeCounters::refused);
    rec.verb = std::uint8_t(write ? Verb::Write : Verb::Force);
    rec.target = var_operand(it->second);
    std::memcpy(rec.value, value, sizeof rec.value);
    p.verb = Verb(rec.verb);
    return queue(rec, std::move(p));
  }
  if (v == "unforce") {
    if (a.empty() || a.size() > 2 || (a.size() == 2 && a[1] != "restore"))
      return refuse("unforce: needs NAME [restore]", &BridgeCounters::refused);
    rec.restore = a.size() == 2 ? 1 : 0;
    if (a[0] == "all") {
      rec.verb = std::uint8_t(Verb::UnforceAll);
    } else {
      const auto it = view.index.find(a[0]);
      if (it == view.index.end() || !view.cell.vars[it->second].forceable)
        return refuse("unforce " + a[0] + ": not allowed (not forceable)",
                      &BridgeCounters::refused);
      rec.verb = std::uint8_t(Verb::Unforce);
      rec.target = var_operand(it->second);
    }
    p.verb = Verb(rec.verb);
    return queue(rec, std::move(p));
  }
  if (v == "pause" || v == "continue") {
    rec.verb = std::uint8_t(v == "pause" ? Verb::Pause : Verb::Continue);
    p.verb = Verb(rec.verb);
    return queue(rec, std::move(p));
  }
  if (v == "step") {
    std::uint64_t n = 1;
    if (!a.empty()) {
      char* end = nullptr;
      n = std::strtoull(a[0].c_str(), &end, 10);
      if (a[0].empty() || *end || n < 1 || n > ipc::kMaxStep)
        return refuse("step: '" + a[0] + "' is not a count from 1 to 1000000",
                      &BridgeCounters::refused);
    }
    rec.verb = std::uint8_t(Verb::Step);
    rec.count = n;
    p.verb = Verb::Step;
    return queue(rec, std::move(p));
  }
  if (v == "break") {
    if (a.size() != 1) return refuse("break: needs one CONDITION", &BridgeCounters::refused);
    // Compiled here, against the layout: plcrun gets code, not text.
    std::vector<ipc::WireOperand> ops;
    const debug::ConditionResolver resolve = [&](const std::string& name,
                                                 std::string& why) -> std::optional<std::uint16_t> {
      const auto o = operand(name, why);
      if (!o) return std::nullopt;
      if (o->kind == WireOperand::Var && view.cell.vars[o->value].type == VarType::STRING) {
        why = "'" + name + "' is a STRING; conditions compare numbers";
        return std::nullopt;
      }
      ops.push_back(*o);
      return std::uint16_t(ops.size() - 1);
    };
    std::string err;
    const auto code = debug::compile_condition(a[0], resolve, err);
    if (!code) return refuse("break: " + err + "\n", &BridgeCounters::refused);
    rec.verb = std::uint8_t(Verb::Break);
    rec.count = 1;
    rec.n_operands = std::uint16_t(ops.size());
    std::copy(ops.begin(), ops.end(), rec.operands);
    rec.n_instrs = std::uint16_t(code->code.size());
    for (std::size_t i = 0; i < code->code.size(); ++i)
      rec.instrs[i] = {std::uint8_t(code->code[i].op), 0, code->code[i].index};
    rec.n_consts = std::uint16_t(code->consts.size());
    for (std::size_t i = 0; i < code->consts.size(); ++i) {
      const debug::Value& k = code->consts[i];
      ipc::WireConst& w = rec.consts[i];
      w.real = k.real ? 1 : 0;
      if (k.real)
        std::memcpy(&w.bits, &k.d, sizeof w.bits);
      else
        w.bits = static_cast<std::uint64_t>(k.i);
    }
    p.verb = Verb::Break;
    return queue(rec, std::move(p));
  }
  if (v == "delete") {
    if (a.size() != 1) return refuse("delete: needs ID|all", &BridgeCounters::refused);
    if (a[0] == "all") {
      rec.verb = std::uint8_t(Verb::DeleteAll);
    } else {
      char* end = nullptr;
      const std::uint64_t id = std::strtoull(a[0].c_str(), &end, 10);
      if (a[0].empty() || *end || id < 1 || id > 0x7fffffff)
        return refuse("delete: no breakpoint " + a[0] + "\n", &BridgeCounters::refused);
      rec.verb = std::uint8_t(Verb::Delete);
      rec.count = id;
    }
    p.verb = Verb(rec.verb);
    return queue(rec, std::move(p));
  }
  return refuse("unknown verb '" + v + "'", &BridgeCounters::refused);
}

std::string Bridge::authenticate(const softplc_hmi::command_t& c) {
  if (!key_) return "";
  auto counted = [this](std::string why, std::uint64_t BridgeCounters::*counter) {
    count(counter);
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

std::optional<softplc_hmi::reply_t> Bridge::queue(ipc::CommandRecord& rec, Pending p) {
  rec.token = next_token_++;
  if (next_token_ == 0) next_token_ = 1;
  rec.generation = view_->generation;
  auto refuse = [&](std::string why) {
    softplc_hmi::reply_t r;
    r.request_id = p.request_id;
    r.client = p.client;
    r.ok = false;
    r.refusal = std::move(why);
    count(&BridgeCounters::refused);
    return std::optional<softplc_hmi::reply_t>(r);
  };
  // Bounded: a client that floods the bus gets "busy", plcrun is not asked.
  if (pending_.size() >= 2 * std::size_t(ipc::kCommandCapacity))
    return refuse("busy: too many commands waiting for the cell");
  if (!regions_->commands().push(rec)) return refuse("busy: the cell's command queue is full");
  p.sent = std::chrono::steady_clock::now();
  pending_.emplace(rec.token, std::move(p));
  if (doorbell_ >= 0) {
    const std::uint64_t one = 1;
    (void)!write(doorbell_, &one, sizeof one);
  }
  return std::nullopt;
}

void Bridge::drain_replies() {
  ipc::Ring<ipc::ReplyRecord> ring = regions_->replies();
  for (std::uint32_t i = 0; i < ring.capacity(); ++i) {
    ipc::ReplyRecord& rec = *reply_;
    const auto got = ring.pop(rec);
    if (got == ipc::Ring<ipc::ReplyRecord>::Pop::Empty) break;
    if (got == ipc::Ring<ipc::ReplyRecord>::Pop::Skipped) continue;
    auto it = pending_.find(rec.token);
    if (it == pending_.end()) continue;  // expired, or not ours
    Pending p = std::move(it->second);
    pending_.erase(it);
    softplc_hmi::reply_t r;
    r.request_id = p.request_id;
    r.client = p.client;
    const std::string text = bounded(rec.text, sizeof rec.text);
    r.ok = rec.reason == std::uint8_t(ipc::Reason::Ok);
    if (r.ok)
      r.text = text;
    else
      r.refusal = text.empty() ? ipc::to_string(ipc::Reason(rec.reason)) : text;
    if (r.ok && p.verb == Verb::Read) {
      for (std::size_t k = 0; k < p.names.size(); ++k) {
        softplc_hmi::var_value_t o;
        o.path = p.names[k];
        const int at = p.operand[k];
        if (at < 0 || at >= rec.n_values) {
          o.error = at < 0 ? p.errors[k] : "no value from the cell";
          r.values.push_back(o);
          continue;
        }
        const ipc::WireValue& w = rec.values[at];
        if (!w.has_value || w.type >= ipc::kVarTypes) {
          o.error = w.has_value ? "a value of unknown type" : bounded(w.error, sizeof w.error);
          r.values.push_back(o);
          continue;
        }
        const VarType t = VarType(w.type);
        o.type = to_string(t);
        o.address = p.addresses[k];
        o.text = value_text(t, w.bytes);
        o.forced = w.forced != 0;
        r.values.push_back(o);
      }
    }
    count(r.ok ? &BridgeCounters::commands : &BridgeCounters::refused);
    publish_reply(std::move(r));
  }
}

void Bridge::expire_pending(Clock::time_point now) {
  // plcrun answers every record it takes; one that stays unanswered this
  // long (its reply ring was full) is forgotten.
  std::erase_if(pending_,
                [now](const auto& e) { return now - e.second.sent > std::chrono::seconds(30); });
}

}  // namespace plc::hmi
