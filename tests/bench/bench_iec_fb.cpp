// IEC FB call cost and the DESIGN.md "Performance targets" reference
// workload: 10,000 FB instances per scan (2,500 each of TON, R_TRIG, CTU and a
// 3-state PROFIdrive-style enable block), our FBs in arrays of instances
// against the same logic hand-written as plain loops over arrays of structs,
// in the same run.
//
// stdout: one `name: value unit` line per figure (medians over repetitions;
// `_min` lines give the fastest repetition), from the CPU time of the
// benchmark thread: the machine is shared, and wall time includes the time
// other processes hold the core. stderr: Google Benchmark's table.
// Repetitions of the two scan variants are interleaved in random order
// (--benchmark_enable_random_interleaving) so machine noise hits both alike.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "plc/fb/iec/counters.hpp"
#include "plc/fb/iec/edges.hpp"
#include "plc/fb/iec/ton.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace {

using namespace std::chrono_literals;
using plc::BOOL;
using plc::ScanContext;
using plc::TIME;
using plc::WORD;

// ---- inputs -------------------------------------------------------------

// Marsaglia xorshift64: fixed seed, identical stream in every variant.
struct Xorshift64 {
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  std::uint64_t next() {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    return s;
  }
};

// Calls f(i, bits) for i in [0, n) with `bits_per_item` random bits per
// item, drawing one 64-bit number per 64 / bits_per_item items.
template <unsigned kBits, class F>
inline void for_each_random(Xorshift64& rng, std::size_t n, F&& f) {
  constexpr std::size_t kPerDraw = 64 / kBits;
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kBits) - 1;
  for (std::size_t b = 0; b < n; b += kPerDraw) {
    std::uint64_t r = rng.next();
    const std::size_t end = std::min(n, b + kPerDraw);
    for (std::size_t i = b; i < end; ++i, r >>= kBits) f(i, unsigned(r & kMask));
  }
}

// TON input: square wave 32 scans on / 32 off, phase-shifted per instance.
inline bool square_wave(std::uint64_t cycle, std::size_t i) { return ((cycle + i) >> 5) & 1; }
// Enable of the drive block: on 200 of 256 scans, phase-shifted per instance.
inline bool drive_enable(std::uint64_t cycle, std::size_t i) {
  return ((cycle + 3 * i) & 255) < 200;
}
// The shared CTU reset: one scan in 8192.
inline bool shared_reset(std::uint64_t cycle) { return (cycle & 8191) == 0; }

constexpr std::size_t kPerType = 2500;
constexpr TIME kTonPt = 20ms;
constexpr plc::INT kCtuPv = 1000;

// STW1 control words (PROFIdrive): 047E = OFF1 (ready to switch on),
// 047F = switch on / enable operation, 04FE = fault acknowledge.
constexpr std::uint16_t kStwOff = 0x047E;
constexpr std::uint16_t kStwOn = 0x047F;
constexpr std::uint16_t kStwAck = 0x04FE;

// ---- the FB side ----------------------------------------------------------

// 3-state PROFIdrive-style enable block (bench-only, written as a library FB
// would be): reads ZSW1 bits 0 (ready to switch on), 1 (ready to operate),
// 2 (operation enabled), 3 (fault); writes STW1 and Ready.
struct DriveEnable {
  enum class State : std::uint8_t { Off, SwitchedOn, Operation };
  WORD ZSW{};     // input: status word
  WORD STW{};     // output: control word
  BOOL Enable{};  // input
  BOOL Ready{};   // output: operation enabled
  State state_{};

  void operator()() {
    const bool rtso = ZSW.bit(0), rto = ZSW.bit(1), oe = ZSW.bit(2), fault = ZSW.bit(3);
    // Same control flow as the hand-written loop below (an if chain; a
    // switch may become a jump table, which mispredicts differently).
    if (state_ == State::Off) {
      if (!fault && Enable && rtso) state_ = State::SwitchedOn;
    } else if (state_ == State::SwitchedOn) {
      if (fault || !Enable)
        state_ = State::Off;
      else if (rto && oe)
        state_ = State::Operation;
    } else if (fault || !Enable || !oe) {
      state_ = State::Off;
    }
    STW = state_ != State::Off ? kStwOn : (fault ? kStwAck : kStwOff);
    Ready = state_ == State::Operation;
  }

  PLC_REFLECT(Enable, ZSW, STW, Ready, state_)
};

struct FbWorld {
  ScanContext ctx{};
  Xorshift64 rng{};
  std::array<plc::iec::TON, kPerType> ton{};
  std::array<plc::iec::R_TRIG, kPerType> trig{};
  std::array<plc::iec::CTU, kPerType> ctu{};
  std::array<DriveEnable, kPerType> drive{};

  void scan() {
    ctx.now += 1ms;
    const std::uint64_t cycle = ++ctx.cycle;
    for (std::size_t i = 0; i < kPerType; ++i) ton[i](ctx, square_wave(cycle, i), kTonPt);
    for_each_random<1>(rng, kPerType, [&](std::size_t i, unsigned b) { trig[i](b != 0); });
    const bool reset = shared_reset(cycle);
    for_each_random<1>(rng, kPerType,
                       [&](std::size_t i, unsigned b) { ctu[i](b != 0, reset, kCtuPv); });
    for_each_random<4>(rng, kPerType, [&](std::size_t i, unsigned b) {
      DriveEnable& d = drive[i];
      d.ZSW = std::uint16_t(b);
      d.Enable = drive_enable(cycle, i);
      d();
    });
  }
};

// ---- the hand-written side ------------------------------------------------

// What a C++ programmer would write for the same logic: compact structs,
// constants folded in, only the state and outputs that are needed, and the
// same branch-free expressions as the FBs where inputs are random (a branch
// on a random bit costs a misprediction whoever writes it).
struct HwTimer {
  std::int64_t start_ns, et_ns;
  bool q, running;
};
struct HwEdge {
  bool q, m;
};
struct HwCounter {
  std::int16_t cv;
  bool q, prev;
};
struct HwDrive {
  std::uint16_t stw;
  std::uint8_t state;  // 0 off, 1 switched on, 2 operation
  bool ready;
};

struct HwWorld {
  std::int64_t now_ns = 0;
  std::uint64_t cycle = 0;
  Xorshift64 rng{};
  std::array<HwTimer, kPerType> ton{};
  std::array<HwEdge, kPerType> trig{};
  std::array<HwCounter, kPerType> ctu{};
  std::array<HwDrive, kPerType> drive{};

  void scan() {
    now_ns += 1'000'000;
    ++cycle;
    constexpr std::int64_t pt = 20'000'000;
    for (std::size_t i = 0; i < kPerType; ++i) {
      HwTimer& t = ton[i];
      if (square_wave(cycle, i)) {
        if (!t.running) {
          t.running = true;
          t.start_ns = now_ns;
        }
        if (!t.q) {
          const std::int64_t e = now_ns - t.start_ns;
          t.q = e >= pt;
          t.et_ns = t.q ? pt : e;
        }
      } else {
        t.q = t.running = false;
        t.et_ns = 0;
      }
    }
    for_each_random<1>(rng, kPerType, [&](std::size_t i, unsigned b) {
      HwEdge& e = trig[i];
      const bool clk = b != 0;
      e.q = clk & !e.m;
      e.m = clk;
    });
    const bool reset = shared_reset(cycle);
    for_each_random<1>(rng, kPerType, [&](std::size_t i, unsigned b) {
      HwCounter& c = ctu[i];
      const bool cu = b != 0;
      const bool up = cu & !c.prev & (c.cv < 32767);
      c.prev = cu;
      c.cv = reset ? std::int16_t{0} : std::int16_t(c.cv + up);
      c.q = c.cv >= kCtuPv;
    });
    for_each_random<4>(rng, kPerType, [&](std::size_t i, unsigned b) {
      HwDrive& d = drive[i];
      const bool rtso = b & 1, rto = b & 2, oe = b & 4, fault = b & 8;
      const bool en = drive_enable(cycle, i);
      if (d.state == 0) {
        if (!fault && en && rtso) d.state = 1;
      } else if (d.state == 1) {
        if (fault || !en)
          d.state = 0;
        else if (rto && oe)
          d.state = 2;
      } else if (fault || !en || !oe) {
        d.state = 0;
      }
      d.stw = d.state ? kStwOn : (fault ? kStwAck : kStwOff);
      d.ready = d.state == 2;
    });
  }
};

// Both worlds must compute the same outputs, or the comparison is void.
bool worlds_agree(const FbWorld& f, const HwWorld& h) {
  for (std::size_t i = 0; i < kPerType; ++i) {
    if (f.ton[i].Q != h.ton[i].q || f.ton[i].ET.count() != h.ton[i].et_ns) return false;
    if (f.trig[i].Q != h.trig[i].q) return false;
    if (f.ctu[i].Q != h.ctu[i].q || f.ctu[i].CV != h.ctu[i].cv) return false;
    if (f.drive[i].STW != h.drive[i].stw || f.drive[i].Ready != h.drive[i].ready) return false;
  }
  return true;
}

// ---- benchmarks -------------------------------------------------------------

void BM_scan_10k_fbs(benchmark::State& state) {
  auto w = std::make_unique<FbWorld>();
  benchmark::DoNotOptimize(w.get());
  for (auto _ : state) {
    w->scan();
    benchmark::ClobberMemory();  // outputs are observed after every scan
  }
  state.counters["calls"] = 4 * kPerType;
}

void BM_scan_10k_handwritten(benchmark::State& state) {
  auto w = std::make_unique<HwWorld>();
  benchmark::DoNotOptimize(w.get());
  for (auto _ : state) {
    w->scan();
    benchmark::ClobberMemory();
  }
  state.counters["calls"] = 4 * kPerType;
}

// Per-call cost: kPerType instances per iteration, inputs varying per scan.
// TON: each IN toggles with probability 1/8 per scan, so across the array the
// IN values are random (the worst case for branch prediction).
void BM_ton_call(benchmark::State& state) {
  auto ton = std::make_unique<std::array<plc::iec::TON, kPerType>>();
  benchmark::DoNotOptimize(ton.get());
  Xorshift64 rng;
  ScanContext ctx{};
  std::array<bool, kPerType> in{};
  for (auto _ : state) {
    ctx.now += 1ms;
    // IN toggles with probability 1/8 per scan: runs shorter and longer than PT.
    for_each_random<3>(rng, kPerType, [&](std::size_t i, unsigned b) {
      in[i] = in[i] != (b == 7);
      (*ton)[i](ctx, in[i], 5ms);
    });
    benchmark::ClobberMemory();
  }
  state.counters["calls"] = kPerType;
}

// TON with the reference workload's input: a square wave 32 on / 32 off,
// phase-shifted per instance (neighbouring instances mostly agree, so the
// branches on IN predict well).
void BM_ton_call_square(benchmark::State& state) {
  auto ton = std::make_unique<std::array<plc::iec::TON, kPerType>>();
  benchmark::DoNotOptimize(ton.get());
  ScanContext ctx{};
  for (auto _ : state) {
    ctx.now += 1ms;
    const std::uint64_t cycle = ++ctx.cycle;
    for (std::size_t i = 0; i < kPerType; ++i) (*ton)[i](ctx, square_wave(cycle, i), kTonPt);
    benchmark::ClobberMemory();
  }
  state.counters["calls"] = kPerType;
}

void BM_r_trig_call(benchmark::State& state) {
  auto trig = std::make_unique<std::array<plc::iec::R_TRIG, kPerType>>();
  benchmark::DoNotOptimize(trig.get());
  Xorshift64 rng;
  for (auto _ : state) {
    for_each_random<1>(rng, kPerType, [&](std::size_t i, unsigned b) { (*trig)[i](b != 0); });
    benchmark::ClobberMemory();
  }
  state.counters["calls"] = kPerType;
}

void BM_ctu_call(benchmark::State& state) {
  auto ctu = std::make_unique<std::array<plc::iec::CTU, kPerType>>();
  benchmark::DoNotOptimize(ctu.get());
  Xorshift64 rng;
  std::uint64_t cycle = 0;
  for (auto _ : state) {
    const bool reset = (++cycle & 1023) == 0;
    for_each_random<1>(rng, kPerType,
                       [&](std::size_t i, unsigned b) { (*ctu)[i](b != 0, reset, kCtuPv); });
    benchmark::ClobberMemory();
  }
  state.counters["calls"] = kPerType;
}

constexpr int kRepetitions = 15;

BENCHMARK(BM_ton_call)->Repetitions(kRepetitions)->MinTime(0.1);
BENCHMARK(BM_ton_call_square)->Repetitions(kRepetitions)->MinTime(0.1);
BENCHMARK(BM_r_trig_call)->Repetitions(kRepetitions)->MinTime(0.1);
BENCHMARK(BM_ctu_call)->Repetitions(kRepetitions)->MinTime(0.1);
BENCHMARK(BM_scan_10k_fbs)->Repetitions(kRepetitions)->MinTime(0.2);
BENCHMARK(BM_scan_10k_handwritten)->Repetitions(kRepetitions)->MinTime(0.2);

// Collects the per-repetition CPU times (ns per iteration) and the "calls"
// counter while the console table goes to stderr.
class CollectingReporter : public benchmark::ConsoleReporter {
 public:
  struct Series {
    std::vector<double> ns_per_iteration;
    double calls = 1;
  };
  std::map<std::string, Series> series;

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration || r.error_occurred) continue;
      Series& s = series[r.run_name.function_name];
      s.ns_per_iteration.push_back(r.GetAdjustedCPUTime() *
                                   benchmark::GetTimeUnitMultiplier(benchmark::kNanosecond) /
                                   benchmark::GetTimeUnitMultiplier(r.time_unit));
      if (auto it = r.counters.find("calls"); it != r.counters.end()) s.calls = it->second;
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}
double minimum(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

}  // namespace

int main(int argc, char** argv) {
  // Equal outputs over 20,000 scans (covers CTU resets and counts past PV).
  {
    auto f = std::make_unique<FbWorld>();
    auto h = std::make_unique<HwWorld>();
    for (int s = 0; s < 20000; ++s) {
      f->scan();
      h->scan();
      if (!worlds_agree(*f, *h)) {
        std::fprintf(stderr, "FB and hand-written outputs differ at scan %d\n", s);
        return 1;
      }
    }
  }

  std::vector<char*> args(argv, argv + argc);
  std::string interleave = "--benchmark_enable_random_interleaving=true";
  args.insert(args.begin() + 1, interleave.data());
  int n = int(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;

  CollectingReporter reporter;
  reporter.SetOutputStream(&std::cerr);
  reporter.SetErrorStream(&std::cerr);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();

  auto& S = reporter.series;
  auto per_call = [&](const char* bm, const char* name) {
    auto it = S.find(bm);
    if (it == S.end() || it->second.ns_per_iteration.empty()) return;
    const double c = it->second.calls;
    std::printf("%s: %.2f ns\n", name, median(it->second.ns_per_iteration) / c);
    std::printf("%s_min: %.2f ns\n", name, minimum(it->second.ns_per_iteration) / c);
  };
  per_call("BM_ton_call", "ton_call");
  per_call("BM_ton_call_square", "ton_call_square_wave");
  per_call("BM_r_trig_call", "r_trig_call");
  per_call("BM_ctu_call", "ctu_call");

  auto fb = S.find("BM_scan_10k_fbs");
  auto hw = S.find("BM_scan_10k_handwritten");
  if (fb != S.end() && hw != S.end() && !fb->second.ns_per_iteration.empty() &&
      !hw->second.ns_per_iteration.empty()) {
    const double a = median(fb->second.ns_per_iteration) / 1000.0;
    const double b = median(hw->second.ns_per_iteration) / 1000.0;
    const double a_min = minimum(fb->second.ns_per_iteration) / 1000.0;
    const double b_min = minimum(hw->second.ns_per_iteration) / 1000.0;
    std::printf("scan_10k_fbs: %.2f us\n", a);
    std::printf("scan_10k_handwritten: %.2f us\n", b);
    std::printf("scan_10k_ratio: %.3f x\n", a / b);
    std::printf("scan_10k_fbs_min: %.2f us\n", a_min);
    std::printf("scan_10k_handwritten_min: %.2f us\n", b_min);
    std::printf("scan_10k_ratio_min: %.3f x\n", a_min / b_min);
    std::printf("scan_10k_per_fb: %.2f ns\n", a * 1000.0 / fb->second.calls);
  }
  return 0;
}
