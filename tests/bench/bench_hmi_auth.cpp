// What the HMI bridge's shared key costs (issue 22). Prints `name: value
// unit` lines:
// - hmi_auth_sign_command: plcctl's side, a `write` command;
// - hmi_auth_verify_command: the bridge's check of it (tag; the epoch and
//   the replay guard add a compare and a map lookup);
// - hmi_auth_sign_reply_10_values: the bridge's reply to a `read` of 10;
// - hmi_auth_sign_description_1000_vars: the description of a cell with
//   1,000 variables (published once a second and on `describe`);
// - hmi_auth_hmac_values_1000_vars: what signing every values_t of 1,000
//   changed values would add per message (encode + HMAC-SHA256). values_t
//   is not signed (hmi-bridge/README.md, "Authentication"): this is the
//   figure behind that choice.
#include <benchmark/benchmark.h>
#include <sodium.h>

#include <cstdio>
#include <vector>

#include "plc/hmi/command_auth.hpp"
#include "plc_bench/collector.hpp"
#include "softplc_hmi/values_t.hpp"

namespace {

using namespace plc;

const hmi::Key kKey = [] {
  hmi::Key k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = std::uint8_t(i);
  return k;
}();
const hmi::TagContext kCmd{"PLC", "demo", "PLC_CMD"};
const hmi::TagContext kReply{"PLC", "demo", "PLC_REPLY"};
const hmi::TagContext kDesc{"PLC", "demo", "PLC_DESC"};

softplc_hmi::command_t write_command() {
  softplc_hmi::command_t c{};
  c.request_id = 0x1234567890LL;
  c.client = "plcctl-host-12345";
  c.verb = "write";
  c.args = {"Tank.high_level", "20000"};
  c.n_args = 2;
  c.counter = 1700000000000000LL;
  return c;
}

void BM_SignCommand(benchmark::State& state) {
  auto c = write_command();
  for (auto _ : state) {
    hmi::sign(c, kKey, kCmd);
    benchmark::DoNotOptimize(c.tag);
  }
}
BENCHMARK(BM_SignCommand)->MinTime(0.5);

void BM_VerifyCommand(benchmark::State& state) {
  auto c = write_command();
  hmi::sign(c, kKey, kCmd);
  for (auto _ : state) benchmark::DoNotOptimize(hmi::verify(c, kKey, kCmd));
}
BENCHMARK(BM_VerifyCommand)->MinTime(0.5);

void BM_SignReply10(benchmark::State& state) {
  softplc_hmi::reply_t r{};
  r.request_id = 42;
  r.client = "plcctl-host-12345";
  r.ok = true;
  for (int i = 0; i < 10; ++i)
    r.values.push_back({"Tank.var" + std::to_string(i), "INT", "", "12345", "", false});
  r.n = 10;
  for (auto _ : state) {
    hmi::sign(r, kKey, kReply);
    benchmark::DoNotOptimize(r.tag);
  }
}
BENCHMARK(BM_SignReply10)->MinTime(0.5);

void BM_SignDescription1000(benchmark::State& state) {
  softplc_hmi::cell_description_t d{};
  d.cell = "demo";
  for (int i = 0; i < 1000; ++i)
    d.vars.push_back({"P.vals[" + std::to_string(i) + "]", "DINT", "", "main", true, false, false});
  d.n = 1000;
  for (auto _ : state) {
    hmi::sign(d, kKey, kDesc);
    benchmark::DoNotOptimize(d.tag);
  }
}
BENCHMARK(BM_SignDescription1000)->MinTime(0.5);

void BM_HmacValues1000(benchmark::State& state) {
  softplc_hmi::values_t m{};
  m.cell = "demo";
  m.task = "main";
  for (int i = 0; i < 1000; ++i) m.values.push_back({i, std::to_string(i * 37 % 100000), false});
  m.n = 1000;
  std::vector<std::uint8_t> buf;
  std::uint8_t tag[crypto_auth_hmacsha256_BYTES];
  for (auto _ : state) {
    buf.resize(std::size_t(m.getEncodedSize()));
    m.encode(buf.data(), 0, int(buf.size()));
    crypto_auth_hmacsha256(tag, buf.data(), buf.size(), kKey.data());
    benchmark::DoNotOptimize(tag);
  }
}
BENCHMARK(BM_HmacValues1000)->MinTime(0.5);

}  // namespace

int main(int argc, char** argv) {
  if (sodium_init() < 0) return 1;
  plc::bench::Collector c;
  if (!plc::bench::run_benchmarks(argc, argv, c)) return 1;
  std::printf("hmi_auth_sign_command: %.0f ns\n", c.cpu("BM_SignCommand"));
  std::printf("hmi_auth_verify_command: %.0f ns\n", c.cpu("BM_VerifyCommand"));
  std::printf("hmi_auth_sign_reply_10_values: %.0f ns\n", c.cpu("BM_SignReply10"));
  std::printf("hmi_auth_sign_description_1000_vars: %.1f us\n",
              c.cpu("BM_SignDescription1000") / 1e3);
  std::printf("hmi_auth_hmac_values_1000_vars: %.1f us\n", c.cpu("BM_HmacValues1000") / 1e3);
  return 0;
}
