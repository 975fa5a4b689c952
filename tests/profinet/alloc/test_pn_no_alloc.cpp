// No heap allocation per cyclic frame (issue 23): once the ARs are up, the
// exchange of cyclic RT frames through the in-memory hub, the controller's
// send/receive/decode path and the simulated device's (PnDevice) allocate
// nothing. A global operator new that counts (its own executable, so that
// no other test shares the replacement) is armed around N cycles after
// start-up; the allocations counted must be zero.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/io/record_request.hpp"
#include "plc/profinet/controller/profinet_plugin.hpp"
#include "profinet/pn_loop.hpp"

namespace {

std::atomic<bool> g_counting{false};
std::atomic<std::uint64_t> g_allocations{0};

void* counted_alloc(std::size_t n, std::size_t align) {
  if (g_counting.load(std::memory_order_relaxed))
    g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (n == 0) n = 1;
  void* p = align > alignof(std::max_align_t)
                ? std::aligned_alloc(align, (n + align - 1) / align * align)
                : std::malloc(n);
  return p;
}

}  // namespace

void* operator new(std::size_t n) {
  if (void* p = counted_alloc(n, 0)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return ::operator new(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  if (void* p = counted_alloc(n, static_cast<std::size_t>(a))) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) { return ::operator new(n, a); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n, 0); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n, 0); }
// The replacements allocate with malloc/aligned_alloc, so free() is the
// right match; GCC, inlining a std::function's new/delete pair, warns
// otherwise (-Wmismatched-new-delete, a false positive here).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace {

using namespace pntest;
namespace io = plc::io;

// Counts the allocations of this thread's code (the lockstep runs on one
// thread) while it lives.
class AllocationWindow {
 public:
  AllocationWindow() {
    g_allocations.store(0);
    g_counting.store(true);
  }
  ~AllocationWindow() { g_counting.store(false); }
  std::uint64_t count() const { return g_allocations.load(); }
};

constexpr int kCycles = 2000;  // 1 ms each: 2,000 frames each way per device

io::ModelParams params(std::initializer_list<std::pair<const char*, const char*>> kv) {
  io::ModelParams p;
  for (auto [k, v] : kv) p.set(k, v);
  return p;
}

// The counter itself: an allocation in the window is seen (else a zero
// below would prove nothing).
TEST(PnNoAllocation, TheCounterSeesAnAllocation) {
  std::uint64_t n = 0;
  {
    AllocationWindow w;
    auto* v = new std::array<std::uint8_t, 100>{};
    n = w.count();
    delete v;
  }
  EXPECT_EQ(n, 1u);
}

// The PROFINET stack alone: our controller and two PnDevices (HIWIN E1,
// telegram 111) on the hub and the UDP network (pn_loop.hpp), IEC
// 61158-6-10 §4.7 RT_CLASS_1 frames every 1 ms in both directions.
TEST(PnNoAllocation, CyclicFramesThroughTheHubAllocateNothing) {
  PnLoop loop;
  for (int i = 0; i < 2; ++i)
    loop.add("hiwin_e1", params({{"telegram", "111"}}),
             std::make_unique<plc::sim::HiwinE1Model>(plc::sim::HiwinE1Config{}));
  ASSERT_TRUE(loop.run_until(
      [&] {
        for (std::size_t i = 0; i < 2; ++i)
          if (!loop.online(i) || loop.devices[i].dev->state() != PnDeviceState::DataExchange)
            return false;
        return true;
      },
      3000));
  loop.run_until([] { return false; }, 100);  // past start-up (records, ApplicationReady)
  std::array<std::uint64_t, 2> in0{}, sent0{};
  for (std::size_t i = 0; i < 2; ++i) {
    in0[i] = loop.ctrl->counters(i).frames_in;
    sent0[i] = loop.devices[i].dev->counters().frames_sent;
  }
  std::uint64_t allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < kCycles; ++k) {
      loop.ctrl->outputs(0)[3] = static_cast<std::uint8_t>(k);  // the data change every cycle
      loop.step();
    }
    allocations = w.count();
  }
  EXPECT_EQ(allocations, 0u) << "heap allocations in " << kCycles << " cycles";
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE(loop.online(i));
    EXPECT_EQ(loop.ctrl->counters(i).frames_in - in0[i], std::uint64_t{kCycles});
    EXPECT_EQ(loop.devices[i].dev->counters().frames_sent - sent0[i], std::uint64_t{kCycles});
    EXPECT_EQ(loop.ctrl->counters(i).bad_total(), 0u);
  }
}

// Record exchanges once the AR is up (hiwin-e1-profinet.md §6.4: a
// PROFIdrive parameter request as WRREC + RDREC, carried by RPC Write and
// Read over the UDP network): the controller's and PnDevice's RPC args,
// NDR bodies and datagrams are built into reused buffers, so after the
// first exchange (the buffers grow to the longest message) none allocates.
TEST(PnNoAllocation, RecordWritesAndReadsAllocateNothingOnceWarm) {
  PnLoop loop;
  loop.add("hiwin_e1", params({{"telegram", "111"}}),
           std::make_unique<plc::sim::HiwinE1Model>(plc::sim::HiwinE1Config{}));
  ASSERT_TRUE(loop.run_until(
      [&] { return loop.online(0) && loop.devices[0].dev->state() == PnDeviceState::DataExchange; },
      3000));
  loop.run_until([] { return false; }, 100);
  io::RecordRequest wr, rd;
  // Read PNU 922 (telegram selection), reference `ref`.
  auto exchange = [&](std::uint8_t ref) {
    const std::uint8_t req[] = {ref, 0x01, 0x00, 0x01, 0x10, 0x00, 0x03, 0x9A, 0x00, 0x00};
    if (!wr.prepare_write(0xB02E, req) || !loop.ctrl->link(0).submit(wr)) return false;
    if (!loop.run_until([&] { return !wr.busy(); }, 100)) return false;
    if (wr.status() != io::RecordStatus::Done) return false;
    wr.reset();
    rd.prepare_read(0xB02E);
    if (!loop.ctrl->link(0).submit(rd)) return false;
    if (!loop.run_until([&] { return !rd.busy(); }, 100)) return false;
    const bool ok = rd.status() == io::RecordStatus::Done && rd.data().size() >= 8 &&
                    rd.data()[0] == ref && io::load_be<std::uint16_t>(rd.data(), 6) == 111;
    rd.reset();
    return ok;
  };
  ASSERT_TRUE(exchange(1));  // warm-up: the buffers grow here
  constexpr int kExchanges = 50;
  int ok = 0;
  std::uint64_t allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < kExchanges; ++k) ok += exchange(static_cast<std::uint8_t>(2 + k));
    allocations = w.count();
  }
  EXPECT_EQ(ok, kExchanges);
  EXPECT_EQ(allocations, 0u) << "heap allocations in " << kExchanges << " record write+read pairs";
  EXPECT_EQ(loop.ctrl->counters(0).records_ok, 2u * (kExchanges + 1));
  EXPECT_TRUE(loop.online(0));
}

// The `profinet` plugin as the PROFINET filling cell runs it
// (programs/filling_cell/cell_profinet.yaml: simulate: true on a mem: link,
// the conveyor's E1 and the NORD PROFIsafe module), stepped in virtual time
// with a scan's latch and publish around each step.
TEST(PnNoAllocation, PluginInVirtualTimeAllocatesNothingPerCycle) {
  plc::profinet::ProfinetPlugin plugin;
  plugin.configure(params({{"interface", "mem:no-alloc-cell"},
                           {"simulate", "true"},
                           {"log", "false"},
                           {"data_hold_factor", "3"}}));
  plugin.add_device(
      {"conveyor", "hiwin_e1",
       params({{"telegram", "111"}, {"station_name", "conveyor"}, {"ip", "192.168.0.10"}})});
  plugin.add_device({"safety", "nord_profisafe",
                     params({{"station_name", "safety"},
                             {"ip", "192.168.0.11"},
                             {"dip_address", "1"},
                             {"p802_3", "1"},
                             {"p840", "0"}})});
  plugin.start(io::ClockMode::Virtual);
  std::array<std::uint8_t, 64> in{}, out{};
  plc::TIME now{0};
  auto cycle = [&] {
    now += std::chrono::milliseconds(1);
    for (std::size_t d = 0; d < 2; ++d) plugin.latch_inputs(d, in);
    for (std::size_t d = 0; d < 2; ++d) plugin.publish_outputs(d, out);
    plugin.step(now, std::chrono::milliseconds(1));
  };
  auto online = [&] {
    return plugin.link(0).live_state() == io::DeviceState::Online &&
           plugin.link(1).live_state() == io::DeviceState::Online;
  };
  for (int k = 0; k < 3000 && !online(); ++k) cycle();
  ASSERT_TRUE(online()) << plugin.diagnostics(0) << "\n" << plugin.diagnostics(1);
  for (int k = 0; k < 100; ++k) cycle();
  const std::uint64_t in0 = plugin.controller().counters(0).frames_in;
  std::uint64_t allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < kCycles; ++k) cycle();
    allocations = w.count();
  }
  EXPECT_EQ(allocations, 0u) << "heap allocations in " << kCycles << " cycles";
  EXPECT_TRUE(online());
  EXPECT_EQ(plugin.controller().counters(0).frames_in - in0, std::uint64_t{kCycles});
  plugin.stop();
}

}  // namespace
