#include "client.hpp"

#include <unistd.h>

#include <stdexcept>

namespace plc::hmi {

Client::Client(const std::string& url, const std::string& prefix, std::optional<Key> key,
               std::chrono::milliseconds timeout)
    : ch_(prefix), key_(key), timeout_(timeout) {
  std::string err;
  transport_ = open_transport(url, err);
  if (!transport_) throw std::runtime_error("--url: " + err);
  client_ = "plcctl-" + std::to_string(::getpid());
  // Counters only go up, also across runs of plcctl: start from the clock.
  next_id_ = std::chrono::duration_cast<std::chrono::microseconds>(
                 std::chrono::system_clock::now().time_since_epoch())
                 .count();
}

std::optional<softplc_hmi::reply_t> Client::command(const std::string& verb,
                                                    const std::vector<std::string>& args,
                                                    std::string& err) {
  softplc_hmi::command_t c{};
  c.request_id = next_id_++;
  c.client = client_;
  c.verb = verb;
  c.args = args;
  c.n_args = int(args.size());
  c.counter = c.request_id;
  if (key_) sign(c, *key_);
  std::optional<softplc_hmi::reply_t> got;
  struct Match {
    std::optional<softplc_hmi::reply_t>* out;
    std::int64_t id;
    std::string client;
    void on(const softplc_hmi::reply_t& r) {
      if (r.request_id == id && r.client == client) *out = r;
    }
  } m{&got, c.request_id, client_};
  auto* s = subscribe_checked<softplc_hmi::reply_t>(*transport_, ch_.reply, &m);
  transport_->publish(ch_.cmd, &c);
  wait([&] { return got.has_value(); });
  transport_->unsubscribe(s);
  if (!got)
    err = "no reply on " + ch_.reply + " within " + std::to_string(timeout_.count()) +
          " ms (is the cell running with an hmi: section, on this url and prefix?)";
  return got;
}

std::optional<softplc_hmi::cell_description_t> Client::describe(std::string& err) {
  std::optional<softplc_hmi::cell_description_t> got;
  Catch<softplc_hmi::cell_description_t> c{&got};
  auto* s = subscribe_checked<softplc_hmi::cell_description_t>(*transport_, ch_.desc, &c);
  // Asked for; a bridge also sends it every second, and a replayed log
  // (lcm-logplayer) has those, so the reply is not needed.
  std::string ignored;
  command("describe", {}, ignored);
  wait([&] { return got.has_value(); });
  transport_->unsubscribe(s);
  if (!got)
    err = "no cell description on " + ch_.desc + " within " + std::to_string(timeout_.count()) +
          " ms (is the cell running with an hmi: section, on this url and prefix?)";
  return got;
}

}  // namespace plc::hmi
