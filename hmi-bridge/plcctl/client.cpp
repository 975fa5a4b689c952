#include "client.hpp"

#include <unistd.h>

#include <algorithm>
#include <stdexcept>

#include "plc/hmi/utime.hpp"

namespace plc::hmi {

namespace {

std::string host_name() {
  char h[256] = {};
  if (::gethostname(h, sizeof h - 1) != 0 || !h[0]) return "host";
  return h;
}

std::string replies(int n) { return n == 1 ? "1 reply" : std::to_string(n) + " replies"; }

}  // namespace

Client::Client(const std::string& url, const std::string& prefix, std::optional<Key> key,
               std::chrono::milliseconds timeout)
    : ch_(prefix), prefix_(prefix), key_(key), timeout_(timeout) {
  std::string err;
  transport_ = open_transport(url, err);
  if (!transport_) throw std::runtime_error("--url: " + err);
  // The host too: two machines' plcctl may have the same pid.
  client_ = "plcctl-" + host_name() + "-" + std::to_string(::getpid());
}

// Counters only go up within a bridge's epoch, also across runs of plcctl
// and between clients (the bridge's replay floor compares them): the wall
// clock in microseconds, one more than the last when the clock stands still.
std::int64_t Client::next_counter() {
  last_counter_ = std::max(utime_now(), last_counter_ + 1);
  return last_counter_;
}

std::optional<softplc_hmi::reply_t> Client::command(const std::string& verb,
                                                    const std::vector<std::string>& args,
                                                    std::string& err) {
  if (key_ && !cell_ && !describe(err)) return std::nullopt;
  auto r = command_once(verb, args, err);
  // Refused as stale: the bridge started again after the description we
  // signed for. The signed refusal names the epoch to use: once more.
  if (key_ && r && !r->ok && r->refusal.rfind("stale epoch", 0) == 0 && epoch_of(*r) != epoch_) {
    epoch_ = epoch_of(*r);
    r = command_once(verb, args, err);
  }
  return r;
}

std::optional<softplc_hmi::reply_t> Client::command_once(const std::string& verb,
                                                         const std::vector<std::string>& args,
                                                         std::string& err) {
  softplc_hmi::command_t c{};
  c.request_id = random_request_id();
  c.client = client_;
  c.verb = verb;
  c.args = args;
  c.n_args = int(args.size());
  c.counter = next_counter();
  if (key_) {
    set_epoch(c, epoch_);
    sign(c, *key_, {prefix_, *cell_, ch_.cmd});
  }
  std::optional<softplc_hmi::reply_t> got;
  struct Match {
    std::optional<softplc_hmi::reply_t>* out;
    const softplc_hmi::command_t* sent;
    const std::optional<Key>* key;
    TagContext ctx;
    int bad_tags = 0;  // addressed to our request, tag missing or wrong
    void on(const softplc_hmi::reply_t& r) {
      if (*out || r.request_id != sent->request_id || r.client != sent->client) return;
      if (*key && !verify(r, **key, ctx)) {
        ++bad_tags;
        return;
      }
      *out = r;
    }
  } m{&got, &c, &key_, {prefix_, cell_.value_or(""), ch_.reply}};
  auto* s = subscribe_checked<softplc_hmi::reply_t>(*transport_, ch_.reply, &m);
  transport_->publish(ch_.cmd, &c);
  if (on_sent) on_sent(c);
  wait([&] { return got.has_value(); });
  transport_->unsubscribe(s);
  if (!got) {
    err = "no reply on " + ch_.reply + " within " + std::to_string(timeout_.count()) + " ms";
    if (m.bad_tags)
      err += ": " + replies(m.bad_tags) +
             " to this request refused, tag missing or not verifying with --key (forged, or "
             "the cell has another key or none)";
    else
      err += " (is the cell running with an hmi: section, on this url and prefix?)";
  }
  return got;
}

std::optional<softplc_hmi::cell_description_t> Client::describe(std::string& err) {
  std::optional<softplc_hmi::cell_description_t> got;
  struct Verified {
    std::optional<softplc_hmi::cell_description_t>* out;
    const std::optional<Key>* key;
    std::string prefix, channel;
    int bad_tags = 0;
    void on(const softplc_hmi::cell_description_t& d) {
      if (*out) return;
      // The description names its cell and epoch; the tag binds both to
      // this prefix and channel.
      if (*key && !verify(d, **key, {prefix, d.cell, channel})) {
        ++bad_tags;
        return;
      }
      *out = d;
    }
  } v{&got, &key_, prefix_, ch_.desc};
  auto* s = subscribe_checked<softplc_hmi::cell_description_t>(*transport_, ch_.desc, &v);
  // Asked for without a tag (the epoch to sign for is what it tells); a
  // bridge also sends it every second, and a replayed log (lcm-logplayer)
  // has those, so the reply is not waited for.
  softplc_hmi::command_t c{};
  c.request_id = random_request_id();
  c.client = client_;
  c.verb = "describe";
  c.counter = next_counter();
  transport_->publish(ch_.cmd, &c);
  if (on_sent) on_sent(c);
  wait([&] { return got.has_value(); });
  transport_->unsubscribe(s);
  if (!got) {
    err = "no cell description on " + ch_.desc + " within " + std::to_string(timeout_.count()) +
          " ms";
    if (v.bad_tags)
      err += ": " + std::to_string(v.bad_tags) +
             " refused, tag missing or not verifying with --key (the cell has another key or "
             "none, or they are forged)";
    else
      err += " (is the cell running with an hmi: section, on this url and prefix?)";
    return got;
  }
  if (key_) {
    cell_ = got->cell;
    epoch_ = epoch_of(*got);
  }
  return got;
}

}  // namespace plc::hmi
