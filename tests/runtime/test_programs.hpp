// Small programs used by the runtime tests (registered by name).
#pragma once

#include <algorithm>
#include <atomic>
#include <string>
#include <vector>

#include "plc/fb/iec/iec.hpp"
#include "plc/io/device_port.hpp"
#include "plc/io/located.hpp"
#include "plc/io/record_request.hpp"
#include "plc/program.hpp"

namespace plctest {

using namespace plc;

// Records every scan's timestamp (and a global sequence number, to check the
// order in which tasks run within one tick).
class ReleaseLog : public ProgramBase<ReleaseLog> {
 public:
  ReleaseLog() { times.reserve(20000); }
  void cycle(const ScanContext& ctx) override {
    times.push_back(ctx.now.count());
    cycles.push_back(ctx.cycle);
    order.push_back(next_sequence()++);
  }
  static std::uint64_t& next_sequence() {
    static std::uint64_t s = 0;
    return s;
  }
  std::vector<std::int64_t> times;
  std::vector<std::uint64_t> cycles, order;
  DINT scans = 0;
  PLC_REFLECT(scans)
};

// Busy-waits until its thread has used `spin_us` microseconds of CPU in a
// scan while `spin` is TRUE (to trip the watchdog: the real-time one times
// the wall clock, which runs at least as far; the virtual-time one the
// scan thread's CPU time); drives a located output every scan.
class Spinner : public ProgramBase<Spinner> {
 public:
  io::Located<INT> out{"%QW0"};
  io::Located<BOOL> lamp{"%QX4.0"};
  BOOL spin = false;
  DINT spin_us = 50000;
  DINT scans = 0;
  void cycle(const ScanContext& ctx) override;
  PLC_REFLECT(out, lamp, spin, spin_us, scans)
};

// A scan that does not return until the test lets it (a runaway program,
// as far as the runtime can tell: bounded at 60 s so a failing test ends).
// It counts its live instances, notes how many were alive when its scan
// came back, and then writes a located output, as programs do: after its
// runtime is gone, that is only safe if the runtime kept the program and
// its task's image alive for it.
class Runaway : public ProgramBase<Runaway> {
 public:
  Runaway() { live.fetch_add(1); }
  ~Runaway() override { live.fetch_sub(1); }
  Runaway(const Runaway&) = delete;
  Runaway& operator=(const Runaway&) = delete;
  io::Located<INT> out{"%QW0"};
  DINT scans = 0;
  void cycle(const ScanContext& ctx) override;
  PLC_REFLECT(out, scans)
  static inline std::atomic<bool> release{false};     // the test lets the scan return
  static inline std::atomic<int> live{0};             // Runaway objects alive
  static inline std::atomic<int> live_at_return{-1};  // `live` when a spin ended
};

// Sets one bit of %QB8 (which bit: `bit`) and counts into %MW10+2*bit: two
// instances in two tasks share bytes without clobbering each other.
class BitWriter : public ProgramBase<BitWriter> {
 public:
  io::Located<BOOL> mine{"%QX8.0"};
  USINT bit = 0;
  BOOL value = true;
  void cycle(const ScanContext&) override { mine = value; }
  PLC_REFLECT(mine, bit, value)
};

// A counter and a timer on a loopback device: writes its scan count to the
// device and reads it back one step later.
class LoopCounter : public ProgramBase<LoopCounter> {
 public:
  io::Located<DINT> to_dev{"%QD0"};
  io::Located<DINT> from_dev{"%ID0"};
  iec::TON t;
  iec::CTU ctu;
  DINT count = 0;
  DINT echoed = 0;
  REAL ratio = 0;
  void cycle(const ScanContext& ctx) override {
    ++count;
    to_dev = count;
    echoed = from_dev;
    t.IN = (count / 50) % 2 == 0;
    t.PT = std::chrono::milliseconds(20);
    t(ctx);
    ctu.CU = t.Q;
    ctu.PV = 1000;
    ctu();
    ratio = count ? REAL(echoed) / REAL(count) : 0.0F;
  }
  PLC_REFLECT(to_dev, from_dev, t, ctu, count, echoed, ratio)
};

// Keeps one acyclic read in flight on device 'echo' and counts the
// answers, which it also writes to the device (so a replay compares them).
// While each scan runs it watches its request for a while: an answer must
// never become visible in the middle of a scan.
class RecordPoller : public ProgramBase<RecordPoller> {
 public:
  io::DevicePort dev{"echo"};
  io::Located<DINT> answers_out{"%QD4"};
  DINT answers = 0;
  DINT midscan_changes = 0;
  void cycle(const ScanContext&) override;
  PLC_REFLECT(dev, answers_out, answers, midscan_changes)

 private:
  io::RecordRequest req_;
};

// Sets `first` at the start of its scan and `second` at the end, with
// `work_us` (300 us) of work between: a reader that looks in the middle of a
// scan sees them differ.
class PairWriter : public ProgramBase<PairWriter> {
 public:
  DINT first = 0;
  DINT second = 0;
  DINT work_us = 300;
  void cycle(const ScanContext&) override;
  PLC_REFLECT(first, second, work_us)
};

// Throws on demand (fault isolation).
class Thrower : public ProgramBase<Thrower> {
 public:
  BOOL fire = false;
  io::Located<BOOL> out{"%QX6.0"};
  void cycle(const ScanContext&) override;
  PLC_REFLECT(fire, out)
};

// Reflection coverage: nested FBs, arrays, enums, bit strings, strings.
class Shapes : public ProgramBase<Shapes> {
 public:
  enum class Mode : SINT { Off = 0, Auto = 3 };
  struct Inner {
    iec::R_TRIG edge;
    std::array<iec::TON, 2> timers;
    PLC_REFLECT(edge, timers)
  };
  Inner inner;
  Mode mode = Mode::Auto;
  WORD w = 0x047F;
  STRING name = "cell";
  LREAL x = 1.5;
  std::array<INT, 3> arr{1, 2, 3};
  void cycle(const ScanContext&) override {}
  PLC_REFLECT(inner, mode, w, name, x, arr)
};

// The write policy (reflect.hpp): a block whose internal state indexes a
// buffer, with one internal field made writable behind its check and an
// interface field with a range check.
struct RingLog {
  BOOL In{};     // interface: writable
  INT Depth{4};  // interface, checked: 1..8
  std::array<DINT, 8> buf_{};
  USINT head_ = 0;    // internal: indexes buf_
  DINT scale_ = 1;    // internal, writable after the block's check (1..1000)
  iec::R_TRIG edge_;  // internal FB: all of it, though R_TRIG.CLK is an input
  void operator()() {
    edge_(In);
    if (edge_.Q) {
      // The check keeps debugger writes in range; a program may still set
      // any Depth, so the block clamps it too.
      const int depth = std::clamp<int>(Depth, 1, 8);
      buf_[head_ % depth] = scale_;
      head_ = static_cast<USINT>((head_ + 1) % depth);
    }
  }
  [[nodiscard]] std::string check_depth(INT v) const {
    return v >= 1 && v <= 8 ? "" : "Depth must be 1 .. 8";
  }
  [[nodiscard]] std::string check_scale(DINT v) const {
    return v >= 1 && v <= 1000 ? "" : "scale_ must be 1 .. 1000";
  }
  PLC_REFLECT(In, Depth, buf_, head_, scale_, edge_)
  PLC_INTERNAL(buf_, head_, scale_, edge_)
  PLC_WRITE_CHECK(Depth, check_depth, scale_, check_scale)
};

class Guarded : public ProgramBase<Guarded> {
 public:
  RingLog log;
  DINT scans = 0;
  void cycle(const ScanContext&) override {
    log.In = scans++ % 2 == 0;
    log();
  }
  PLC_REFLECT(log, scans)
};

}  // namespace plctest
