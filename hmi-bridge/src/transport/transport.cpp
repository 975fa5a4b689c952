#include "plc/hmi/transport.hpp"

#include <exception>

#include "plc/hmi/lcm_url.hpp"
#include "plc/hmi/memq_transport.hpp"
#include "plc/hmi/udpm_transport.hpp"

namespace plc::hmi {

Transport::~Transport() = default;

bool Transport::Subscription::matches(std::string_view channel) const {
  if (!re) return channel == pattern;
  // Bounded: a channel has at most 63 characters, the patterns are ours;
  // should the matcher still give up (error_complexity), nobody wants it.
  try {
    return std::regex_match(channel.begin(), channel.end(), *re);
  } catch (const std::regex_error&) {
    return false;
  }
}

Transport::Subscription* Transport::subscribe(const std::string& channel, Handler handler) {
  auto s = std::make_shared<Subscription>();
  s->pattern = channel;
  // Names of letters, digits and '_' (every channel of ours) match exactly;
  // anything else is a regular expression, as in liblcm.
  if (channel.find_first_not_of(
          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
    s->re.emplace(channel, std::regex::ECMAScript);
  s->handler = std::move(handler);
  std::lock_guard<std::mutex> lock(subs_mu_);
  subs_.push_back(s);
  return s.get();
}

void Transport::unsubscribe(Subscription* s) {
  std::lock_guard<std::mutex> lock(subs_mu_);
  for (std::size_t i = 0; i < subs_.size(); ++i)
    if (subs_[i].get() == s) {
      s->active = false;  // a dispatch in progress holds it, and skips it now
      subs_.erase(subs_.begin() + std::ptrdiff_t(i));
      return;
    }
}

bool Transport::subscribed(std::string_view channel) const {
  std::lock_guard<std::mutex> lock(subs_mu_);
  for (const auto& s : subs_)
    if (s->matches(channel)) return true;
  return false;
}

int Transport::dispatch(std::string_view channel, const ReceiveBuffer& rb,
                        TransportCounters& counters) {
  std::vector<std::shared_ptr<Subscription>> to;
  {
    // Handlers run unlocked: they may subscribe, unsubscribe and publish.
    std::lock_guard<std::mutex> lock(subs_mu_);
    for (const auto& s : subs_)
      if (s->matches(channel)) to.push_back(s);
  }
  const std::string name(channel);
  int n = 0;
  for (const auto& s : to) {
    if (!s->active) continue;
    try {
      s->handler(rb, name);
      ++n;
    } catch (const std::exception&) {
      ++counters.handler_exceptions;
    }
  }
  return n;
}

std::unique_ptr<Transport> open_transport(const std::string& url, std::string& error,
                                          const UdpmLimits& limits) {
  const auto u = parse_lcm_url(url, error);
  if (!u) return nullptr;
  if (u->kind == LcmUrl::Kind::Memq) return std::make_unique<MemqTransport>(limits);
  return UdpmTransport::open(*u, limits, error);
}

}  // namespace plc::hmi
