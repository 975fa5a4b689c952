// Hostile messages on the client side (issue 13: malformed messages are
// refused, nothing applied; plcctl must not crash or allocate gigabytes):
// lcm-gen's decoders resize a vector to the count as sent before checking
// the length. plcctl and the bridge decode through one guard,
// plc::hmi::checked_decode / subscribe_checked.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "plc/hmi/checked_decode.hpp"
#include "plc/hmi/memq_transport.hpp"

using namespace plc::hmi;

namespace {

template <class T>
std::vector<std::uint8_t> encoded(const T& m) {
  std::vector<std::uint8_t> b(std::size_t(m.getEncodedSize()));
  EXPECT_EQ(m.encode(b.data(), 0, int(b.size())), int(b.size()));
  return b;
}

void put_int32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) b[at + std::size_t(k)] = std::uint8_t(v >> (24 - 8 * k));
}

softplc_hmi::reply_t reply_with_one_value() {
  softplc_hmi::reply_t r{};
  r.request_id = 7;
  r.client = "c";
  r.ok = true;
  r.values.push_back({"Tank.level", "INT", "%IW0", "12", "", false});
  r.n = 1;
  return r;
}

}  // namespace

// Every shape consumes its type's encoding exactly (the shapes follow
// hmi-bridge/lcm/*.lcm; a changed .lcm file without its shape fails here).
TEST(HmiCheckedDecode, ShapesMatchTheLcmTypes) {
  softplc_hmi::command_t c{};
  c.verb = "read";
  c.args = {"a", "bc"};
  c.n_args = 2;
  softplc_hmi::values_t v{};
  v.values = {{1, "TRUE", true}, {2, "16#00FF", false}};
  v.n = 2;
  softplc_hmi::trace_sample_t t{};
  t.index = {1, 2, 3};
  t.value = {1.0, 2.0, 3.0};
  t.n = 3;
  softplc_hmi::stats_t s{};
  s.tasks.resize(2);
  s.n = 2;
  s.transport_counter = {"datagrams", "bad_fragment"};
  s.transport_count = {5, 1};
  s.n_transport = 2;
  softplc_hmi::cell_description_t d{};
  d.vars.resize(3);
  d.n = 3;
  softplc_hmi::diagnostics_t g{};
  g.devices.resize(2);
  g.n_devices = 2;
  g.alarms.resize(1);
  g.n_alarms = 1;
  softplc_hmi::alarm_t a{};
  a.kind = "device_lost";
  auto round_trip = [](const auto& m) {
    auto b = encoded(m);
    std::remove_cvref_t<decltype(m)> out;
    EXPECT_TRUE(checked_decode(b.data(), b.size(), out)) << decltype(out)::getTypeName();
    b.push_back(0);  // one byte too many: not this type's encoding
    EXPECT_FALSE(checked_decode(b.data(), b.size(), out)) << decltype(out)::getTypeName();
  };
  round_trip(c);
  round_trip(reply_with_one_value());
  round_trip(v);
  round_trip(t);
  round_trip(s);
  round_trip(d);
  round_trip(g);
  round_trip(a);
}

// A reply whose count is -1 or 2^31-1 with one value behind it: lcm-gen's
// decoder alone throws std::length_error or allocates gigabytes; the guard
// refuses it without decoding.
TEST(HmiCheckedDecode, HostileCountsAreRefusedBeforeDecoding) {
  const auto good = encoded(reply_with_one_value());
  // reply_t: fingerprint, request_id, client "c", ok, refusal "", text "", n.
  const std::size_t n_at = 8 + 8 + (4 + 2) + 1 + (4 + 1) + (4 + 1);
  for (std::uint32_t n : {0xFFFFFFFFU, 0x7FFFFFFFU, 2U}) {
    auto b = good;
    put_int32(b, n_at, n);
    softplc_hmi::reply_t out;
    EXPECT_FALSE(checked_decode(b.data(), b.size(), out)) << n;
  }
  auto b = good;
  put_int32(b, 8 + 8, 0);  // a string length of 0 (no NUL): std::length_error in lcm-gen
  softplc_hmi::reply_t out;
  EXPECT_FALSE(checked_decode(b.data(), b.size(), out));
  for (std::size_t cut = 0; cut < good.size(); ++cut)
    EXPECT_FALSE(checked_decode(good.data(), cut, out)) << cut;
}

// Through a transport as plcctl receives it (memq://, in-process): hostile
// replies are dropped (on_malformed), the good one after them arrives.
TEST(HmiCheckedDecode, PlcctlSubscriptionDropsHostileMessages) {
  MemqTransport memq;
  struct Sink {
    int good = 0, malformed = 0;
    void on(const softplc_hmi::reply_t& r) { good += r.request_id == 7; }
    void on_malformed() { ++malformed; }
  } sink;
  auto* s = subscribe_checked<softplc_hmi::reply_t>(memq, "PLC_REPLY", &sink);
  auto b = encoded(reply_with_one_value());
  auto hostile = b;
  put_int32(hostile, 8 + 8 + 6 + 1 + 5 + 5, 0xFFFFFFFFU);
  memq.publish("PLC_REPLY", hostile.data(), unsigned(hostile.size()));
  put_int32(hostile, 8 + 8 + 6 + 1 + 5 + 5, 0x7FFFFFFFU);
  memq.publish("PLC_REPLY", hostile.data(), unsigned(hostile.size()));
  memq.publish("PLC_REPLY", b.data(), unsigned(b.size()));
  for (int i = 0; i < 10 && sink.good + sink.malformed < 3; ++i) memq.handle_timeout(0);
  memq.unsubscribe(s);
  EXPECT_EQ(sink.malformed, 2);
  EXPECT_EQ(sink.good, 1);
}
