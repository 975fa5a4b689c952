// DriveAxis reads and writes telegram 111 (Table 3.2.2 of
// shared/specs/hiwin-e1-profinet.md) with fewer instructions than a
// word-by-word Telegram111In::decode / Telegram111Out::encode: several
// status words swapped and masked together, members stored as one word,
// STW1 composed from a packed test of the task requests. These tests compare
// every field and every byte with the plain word-by-word forms over random
// telegrams and random axis states; a shortcut that reads a wrong byte, masks
// a wrong bit or stores into a neighbouring member fails here.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <random>

#include "plc/fb/drive/drive_axis.hpp"
#include "plc/fb/drive/mc_blocks.hpp"
#include "plc/fb/drive/scaling.hpp"
#include "plc/fb/drive/sign_of_life.hpp"
#include "plc/fb/drive/telegrams.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/io/device_link.hpp"

namespace plc::drive {
namespace {

using namespace std::chrono_literals;

// What begin_scan() reads from a telegram 111, field by field (the decode
// as it was before the shortcuts).
TEST(Table3_2_2, Telegram111ReadEqualsDecodeOfEveryField) {
  std::array<std::uint8_t, Telegram111In::kBytes> in{};
  std::array<std::uint8_t, Telegram111Out::kBytes> out{};
  DriveAxis a;
  a.Telegram = 111;
  a.Port.bind(in, out, nullptr);
  std::mt19937 rng(111);
  for (int i = 0; i < 20000; ++i) {
    for (auto& b : in) b = static_cast<std::uint8_t>(rng());
    if (i % 100 == 0) {
      a.RefSpeedRpm = 500 + rng() % 6000;
      a.CuPerRev = 1 + rng() % 1000000;
    }
    // Members next to the decoded ones that telegram 111 does not carry.
    a.AKTSATZ = 0xA55A;
    a.G1_ZSW = 0x5AA5;
    a.G1_XIST1 = 0x12345678u;
    a.G1_XIST2 = 0x9ABCDEF0u;
    a.begin_scan(ScanContext{std::chrono::milliseconds(i), 1ms, static_cast<std::uint64_t>(i)});
    const auto t = Telegram111In::decode(in);
    ASSERT_EQ(a.ZSW1.value, t.zsw1.word()) << i;
    ASSERT_EQ(a.POS_ZSW1.value, t.pos_zsw1.word()) << i;
    ASSERT_EQ(a.POS_ZSW2.value, t.pos_zsw2.word()) << i;
    ASSERT_EQ(a.ZSW2.value, t.zsw2.word()) << i;
    ASSERT_EQ(a.MELDW.value, t.meldw.word()) << i;
    ASSERT_EQ(a.XIST_A, t.xist_a) << i;
    ASSERT_EQ(a.NIST_B, t.nist_b) << i;
    ASSERT_EQ(a.FAULT_CODE, t.fault_code) << i;
    ASSERT_EQ(a.WARN_CODE, t.warn_code) << i;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(a.ActPosition),
              std::bit_cast<std::uint64_t>(static_cast<double>(t.xist_a)));
    ASSERT_EQ(std::bit_cast<std::uint64_t>(a.ActVelocity),
              std::bit_cast<std::uint64_t>(
                  rpm_to_cu_per_s(nist_b_to_speed(t.nist_b, a.RefSpeedRpm), a.CuPerRev)));
    ASSERT_EQ(a.AKTSATZ.value, 0xA55A);
    ASSERT_EQ(a.G1_ZSW.value, 0x5AA5);
    ASSERT_EQ(a.G1_XIST1, 0x12345678u);
    ASSERT_EQ(a.G1_XIST2, 0x9ABCDEF0u);
    ASSERT_EQ(a.prev_xist_, t.xist_a);
  }
}

// commit() on telegram 111 as it was written before the shortcuts: STW1
// bit by bit, the words stored in the members and encoded from there.
struct Reference {
  std::array<std::uint8_t, Telegram111Out::kBytes> out{};
  WORD STW1, STW2, POS_STW1, POS_STW2, SATZANW;
  bool stw6_sent = false, restart_inhibit = false;
};
Reference reference_commit(DriveAxis a) {
  Reference r;
  std::uint16_t stw1 = Stw1Pos::kControlByPlc;
  if (a.RestartInhibit && a.State != AxisState::ErrorStop && !a.PowerRequest)
    a.RestartInhibit = false;
  const bool power = a.CommOk && a.PowerRequest && !a.InhibitPower && !a.drive_fault() &&
                     !a.RestartInhibit && a.State != AxisState::ErrorStop;
  if (power) {
    stw1 |= Stw1Pos::kNoCoastStop | Stw1Pos::kNoQuickStop | Stw1Pos::kEnableOperation;
    if (!(a.ZSW1 & Zsw1Pos::kSwitchOnInhibited)) stw1 |= Stw1Pos::kOn;
  } else {
    const StopMode m = a.CommOk && !a.InhibitPower ? a.PowerStopMode : StopMode::Off1Ramp;
    if (m != StopMode::Off2Coast) stw1 |= Stw1Pos::kNoCoastStop;
    if (m != StopMode::Off3Quick) stw1 |= Stw1Pos::kNoQuickStop;
  }
  if (a.AckRequest) stw1 |= Stw1Pos::kFaultAck;
  r.STW2 = static_cast<std::uint16_t>(a.sol_out_ << 12);
  if (!a.RejectTask) stw1 |= Stw1Pos::kNoRejectTask;
  if (!a.IntermediateStop) stw1 |= Stw1Pos::kNoIntermediateStop;
  if (a.stw6_) stw1 |= Stw1Pos::kActivateTask;
  if (a.JogRequest1) stw1 |= Stw1Pos::kJog1;
  if (a.JogRequest2) stw1 |= Stw1Pos::kJog2;
  if (a.homing_bit_) stw1 |= Stw1Pos::kStartHoming;
  r.STW1 = stw1;
  r.stw6_sent = a.stw6_;
  r.POS_STW1 = static_cast<std::uint16_t>(
      PosStw1::kActivateMdi | ((a.MDI_MODE & MdiMode::kAbsolute) ? PosStw1::kAbsolute : 0));
  r.POS_STW2 = a.SetReferenceRequest ? PosStw2::kSetReferencePoint : 0;
  r.SATZANW = Satzanw::kActivateMdi;
  r.restart_inhibit = a.RestartInhibit;
  Telegram111Out t;
  t.stw1 = Stw1Pos::from(r.STW1);
  t.pos_stw1 = PosStw1::from(r.POS_STW1);
  t.pos_stw2 = PosStw2::from(r.POS_STW2);
  t.stw2 = Stw2::from(r.STW2);
  t.override_ = a.OVERRIDE;
  t.mdi_tarpos = a.MDI_TARPOS;
  t.mdi_velocity = a.MDI_VELOCITY;
  t.mdi_acc = a.MDI_ACC;
  t.mdi_dec = a.MDI_DEC;
  t.encode(r.out);
  return r;
}

TEST(Table3_2_2, Telegram111CommitEqualsEncodeOfEveryState) {
  std::array<std::uint8_t, Telegram111In::kBytes> in{};
  std::array<std::uint8_t, Telegram111Out::kBytes> out{};
  DriveAxis a;
  a.Telegram = 111;
  a.Port.bind(in, out, nullptr);
  std::mt19937 rng(7);
  auto flag = [&rng](unsigned one_in) { return rng() % one_in == 0; };
  for (int i = 0; i < 100000; ++i) {
    // Mostly the common values, each of them now and then otherwise.
    a.CommOk = !flag(8);
    a.PowerRequest = !flag(4);
    a.InhibitPower = flag(8);
    a.RestartInhibit = flag(4);
    a.AckRequest = flag(6);
    a.State = static_cast<AxisState>(rng() % 8);
    a.PowerStopMode = static_cast<StopMode>(rng() % 3);
    a.ZSW1 = static_cast<std::uint16_t>(rng());
    a.JogRequest1 = flag(5);
    a.JogRequest2 = flag(5);
    a.IntermediateStop = flag(5);
    a.RejectTask = flag(5);
    a.stw6_ = flag(3);
    a.homing_bit_ = flag(5);
    a.SetReferenceRequest = flag(5);
    a.MDI_MODE = static_cast<std::uint16_t>(rng());
    a.sol_out_ = static_cast<std::uint8_t>(rng() % 16);
    a.OVERRIDE = static_cast<std::uint16_t>(rng());
    a.MDI_TARPOS = static_cast<DINT>(rng());
    a.MDI_VELOCITY = static_cast<DINT>(rng());
    a.MDI_ACC = static_cast<INT>(rng());
    a.MDI_DEC = static_cast<INT>(rng());
    const Reference want = reference_commit(a);
    for (auto& b : out) b = static_cast<std::uint8_t>(rng());
    a.commit();
    ASSERT_EQ(out, want.out) << i;
    ASSERT_EQ(a.STW1.value, want.STW1.value) << i;
    ASSERT_EQ(a.STW2.value, want.STW2.value) << i;
    ASSERT_EQ(a.POS_STW1.value, want.POS_STW1.value) << i;
    ASSERT_EQ(a.POS_STW2.value, want.POS_STW2.value) << i;
    ASSERT_EQ(a.SATZANW.value, want.SATZANW.value) << i;
    ASSERT_EQ(a.stw6_sent_, want.stw6_sent) << i;
    ASSERT_EQ(a.RestartInhibit, want.restart_inhibit) << i;
  }
}

}  // namespace
}  // namespace plc::drive

namespace plc::drive {
namespace {

// MC_Power::operator() as it was before it skipped the EnableTimeout
// bookkeeping while Status (the count restarts every such scan anyway).
void reference_power(MC_Power& p, const ScanContext& ctx, DriveAxis& axis) {
  const bool mode_ok = p.StopMode >= 0 && p.StopMode <= 2;
  axis.PowerRequest = p.Enable && mode_ok;
  axis.RequireEnableEdgeAfterReset = p.RequireEnableEdgeAfterReset;
  if (mode_ok) axis.PowerStopMode = static_cast<drive::StopMode>(p.StopMode);
  p.Status = axis.CommOk && axis.operation_enabled();
  const std::uint16_t axis_e = axis.axis_error();
  std::uint16_t e = !mode_ok ? kErrMode : axis_e;
  if (!e && p.Enable && axis.RestartInhibit) e = kErrRestartInhibit;
  const bool held_off = axis_e || axis.RestartInhibit || axis.InhibitPower;
  if ((p.Enable && !p.prev_enable_) || held_off) p.enable_since_ = ctx.now;
  p.prev_enable_ = p.Enable;
  if (!e && p.Enable && !p.Status && ctx.now - p.enable_since_ > p.EnableTimeout)
    e = axis.drive_state() == DriveState::SwitchingOnInhibited ? kErrLockout : kErrEnableTimeout;
  if (p.Status) p.enable_since_ = ctx.now;
  p.Error = e != 0;
  p.ErrorID = e;
  p.Valid = p.Enable && !p.Error;
}

// Random axis states held for a few scans (so that the timeout can run out
// and the Enable edges matter), the block inputs changed now and then.
TEST(McPower, EqualsTheFormerBlockOverRandomScans) {
  DriveAxis a;  // not bound: the block's own logic only
  a.set_program_commits(true);
  MC_Power fast, full;
  fast.EnableTimeout = full.EnableTimeout = 20ms;
  std::mt19937 rng(3);
  auto flag = [&rng](unsigned one_in) { return rng() % one_in == 0; };
  TIME now{};
  int timeouts = 0;
  for (int i = 0; i < 200000; ++i) {
    now += 1ms;
    if (flag(10)) {
      a.CommOk = !flag(5);
      a.CommError = flag(6) ? kErrOffline : 0;
      a.ZSW1 = static_cast<std::uint16_t>(flag(2) ? 0x0637 : rng());  // S4 or anything
      a.error_ = flag(8) ? kErrSignOfLife : 0;
      a.RestartInhibit = flag(6);
      a.InhibitPower = flag(8);
    }
    if (flag(15)) {
      fast.Enable = full.Enable = !flag(3);
      fast.StopMode = full.StopMode = static_cast<INT>(flag(10) ? 3 : rng() % 3);
      fast.RequireEnableEdgeAfterReset = full.RequireEnableEdgeAfterReset = flag(4);
    }
    const ScanContext ctx{now, 1ms, static_cast<std::uint64_t>(i)};
    a.begun_ = true;
    a.last_cycle_ = ctx.cycle;
    a.now_ = ctx.now;  // begun: the blocks do not read the (unbound) port
    DriveAxis b = a;
    fast(ctx, a);
    reference_power(full, ctx, b);
    ASSERT_EQ(fast.Status, full.Status) << i;
    ASSERT_EQ(fast.Valid, full.Valid) << i;
    ASSERT_EQ(fast.Error, full.Error) << i;
    ASSERT_EQ(fast.ErrorID.value, full.ErrorID.value) << i;
    ASSERT_EQ(fast.enable_since_, full.enable_since_) << i;
    ASSERT_EQ(fast.prev_enable_, full.prev_enable_) << i;
    ASSERT_EQ(a.PowerRequest, b.PowerRequest) << i;
    ASSERT_EQ(a.PowerStopMode, b.PowerStopMode) << i;
    ASSERT_EQ(a.RequireEnableEdgeAfterReset, b.RequireEnableEdgeAfterReset) << i;
    if (full.ErrorID == kErrEnableTimeout || full.ErrorID == kErrLockout) ++timeouts;
  }
  EXPECT_GT(timeouts, 100);  // the timeout ran out, often
}

}  // namespace
}  // namespace plc::drive

namespace plc::drive {
namespace {

// DriveAxis::begin_scan() on telegram 111 as it was before its fast paths
// (one function, update_state() at its end; the reads of the library's
// advance() and advance_reset() are the same).
void reference_update_state(DriveAxis& a) {
  using Phase = DriveAxis::Phase;
  using Kind = DriveAxis::Kind;
  const std::uint16_t e = a.axis_error();
  if (e) {
    if (a.State != AxisState::ErrorStop) a.abort_all();
    a.latch_error(e);
    a.State = AxisState::ErrorStop;
    a.RestartInhibit = true;
    return;
  }
  if (a.State == AxisState::ErrorStop) return;
  if (!a.operation_enabled()) {
    if (a.State != AxisState::Disabled) a.abort_all();
    a.State = AxisState::Disabled;
    return;
  }
  const bool running =
      a.phase_ == Phase::PreLow || a.phase_ == Phase::Request || a.phase_ == Phase::Running;
  if (a.StopActive || (a.kind_ == Kind::Stop && running)) {
    a.State = AxisState::Stopping;
  } else if (a.kind_ == Kind::Homing && running) {
    a.State = AxisState::Homing;
  } else if (a.kind_ == Kind::Task && running) {
    a.State = a.task_kind_ == TaskKind::Velocity ? AxisState::ContinuousMotion
                                                 : AxisState::DiscreteMotion;
  } else if (a.kind_ == Kind::Halt && running) {
    a.State = AxisState::DiscreteMotion;
  } else if (a.kind_ == Kind::Jog && running) {
    a.State = AxisState::ContinuousMotion;
  } else {
    a.State = AxisState::Standstill;
  }
}

void reference_begin_scan(DriveAxis& a, const ScanContext& ctx) {
  using Phase = DriveAxis::Phase;
  using Kind = DriveAxis::Kind;
  using ResetPhase = DriveAxis::ResetPhase;
  a.begun_ = true;
  a.last_cycle_ = ctx.cycle;
  a.now_ = ctx.now;
  const auto in = a.Port.in();
  const bool shape_ok =
      in.size() >= Telegram111In::kBytes && a.Port.out().size() >= Telegram111Out::kBytes;
  const bool online = a.Port.online();
  if (shape_ok) {
    const auto t = Telegram111In::decode(in);
    a.ZSW1 = t.zsw1.word();
    a.POS_ZSW1 = t.pos_zsw1.word();
    a.POS_ZSW2 = t.pos_zsw2.word();
    a.ZSW2 = t.zsw2.word();
    a.MELDW = t.meldw.word();
    a.XIST_A = t.xist_a;
    a.NIST_B = t.nist_b;
    a.FAULT_CODE = t.fault_code;
    a.WARN_CODE = t.warn_code;
    a.ActPosition = a.XIST_A;
    a.ActVelocity = rpm_to_cu_per_s(nist_b_to_speed(a.NIST_B, a.RefSpeedRpm), a.CuPerRev);
    a.prev_xist_ = a.XIST_A;
    a.have_prev_xist_ = true;
  }
  if (!online) {
    a.SignOfLifeLost = false;
    a.sol_seen_ = false;
    a.sol_stall_ = 0;
  } else if (a.SignOfLifeCheck && shape_ok) {
    const auto s = static_cast<std::uint8_t>((a.ZSW2.value >> 12) & 0xF);
    if (!a.sol_seen_) {
      if (s != 0) {
        a.sol_seen_ = true;
        a.sol_in_last_ = s;
        a.sol_stall_ = 0;
      }
    } else if (s == a.sol_in_last_) {
      if (++a.sol_stall_ > a.SignOfLifeTolerance) a.SignOfLifeLost = true;
    } else {
      a.sol_stall_ = 0;
      a.sol_in_last_ = s;
    }
  }
  a.CommError = !a.Port.bound()    ? kErrOffline
                : !shape_ok        ? kErrTelegram
                : !online          ? kErrOffline
                : a.SignOfLifeLost ? kErrSignOfLife
                                   : 0;
  a.CommOk = a.CommError == 0;
  a.sol_out_ = next_sign_of_life(a.sol_out_);
  const bool running =
      a.phase_ == Phase::PreLow || a.phase_ == Phase::Request || a.phase_ == Phase::Running;
  if (a.kind_ != Kind::None && (running || (a.kind_ == Kind::Halt && a.phase_ == Phase::Done)))
    a.advance();
  if (a.reset_phase_ == ResetPhase::AckLow || a.reset_phase_ == ResetPhase::AckHigh)
    a.advance_reset();
  reference_update_state(a);
}

// Random axis states (commands and resets in every phase, errors, states,
// sign-of-life histories, the device on and off line, quiet scans most
// often) and random telegrams: every member the scan may touch must equal
// the former scan's. A fast path that skips a case it should not fails.
TEST(Table3_2_2, BeginScanEqualsTheFormerScanOverRandomStates) {
  std::array<std::uint8_t, Telegram111In::kBytes> in{};
  std::array<std::uint8_t, Telegram111Out::kBytes> out{};
  io::DeviceLink link;
  std::mt19937 rng(9);
  auto flag = [&rng](unsigned one_in) { return rng() % one_in == 0; };
  int quiet = 0;
  for (int i = 0; i < 200000; ++i) {
    DriveAxis a;
    a.Telegram = 111;
    const bool short_in = flag(50);
    a.Port.bind(std::span<const std::uint8_t>(in.data(), short_in ? 10 : in.size()), out,
                flag(50) ? nullptr : &link);
    link.set_state(flag(10) ? io::DeviceState::Offline : io::DeviceState::Online);
    for (auto& b : in) b = static_cast<std::uint8_t>(rng());
    if (!flag(4)) {  // a drive in operation, mostly without a fault
      io::store_be<std::uint16_t>(in, Telegram111In::kZsw1,
                                  static_cast<std::uint16_t>(flag(8) ? 0x0E3F : 0x0E37));
    }
    a.SignOfLifeCheck = !flag(10);
    a.sol_seen_ = !flag(5);
    a.sol_in_last_ =
        static_cast<std::uint8_t>(flag(2) ? (in[Telegram111In::kZsw2] >> 4) : rng() % 16);
    a.sol_stall_ = static_cast<std::uint16_t>(rng() % 8);
    a.SignOfLifeLost = flag(10);
    a.error_ = flag(8) ? kErrSignOfLife : 0;
    a.State = flag(2) ? AxisState::Standstill : static_cast<AxisState>(rng() % 8);
    a.StopActive = flag(8);
    a.kind_ = static_cast<DriveAxis::Kind>(rng() % 6);
    a.phase_ = flag(2) ? DriveAxis::Phase::Done : static_cast<DriveAxis::Phase>(rng() % 7);
    a.task_kind_ = static_cast<TaskKind>(1 + rng() % 3);
    a.reset_phase_ =
        flag(2) ? DriveAxis::ResetPhase::Idle : static_cast<DriveAxis::ResetPhase>(rng() % 5);
    a.halt_release_ = flag(2);
    a.stw6_sent_ = flag(2);
    a.RestartInhibit = flag(4);
    a.JogRequest1 = flag(4);
    a.IntermediateStop = flag(4);
    a.phase_start_ = std::chrono::milliseconds(rng() % 400);
    a.reset_start_ = std::chrono::milliseconds(rng() % 2000);
    a.reset_timeout_ = std::chrono::seconds(1);
    a.sol_out_ = static_cast<std::uint8_t>(rng() % 16);
    DriveAxis b = a;
    const ScanContext ctx{std::chrono::milliseconds(1000 + i), 1ms, static_cast<std::uint64_t>(i)};
    a.begin_scan(ctx);
    reference_begin_scan(b, ctx);
    if (a.State == AxisState::Standstill && a.CommOk) ++quiet;
    ASSERT_EQ(a.State, b.State) << i;
    ASSERT_EQ(a.RestartInhibit, b.RestartInhibit) << i;
    ASSERT_EQ(a.CommError.value, b.CommError.value) << i;
    ASSERT_EQ(a.CommOk, b.CommOk) << i;
    ASSERT_EQ(a.SignOfLifeLost, b.SignOfLifeLost) << i;
    ASSERT_EQ(a.sol_seen_, b.sol_seen_) << i;
    ASSERT_EQ(a.sol_in_last_, b.sol_in_last_) << i;
    ASSERT_EQ(a.sol_stall_, b.sol_stall_) << i;
    ASSERT_EQ(a.sol_out_, b.sol_out_) << i;
    ASSERT_EQ(a.error_, b.error_) << i;
    ASSERT_EQ(a.kind_, b.kind_) << i;
    ASSERT_EQ(a.phase_, b.phase_) << i;
    ASSERT_EQ(a.cmd_err_, b.cmd_err_) << i;
    ASSERT_EQ(a.stw6_, b.stw6_) << i;
    ASSERT_EQ(a.homing_bit_, b.homing_bit_) << i;
    ASSERT_EQ(a.seen_traversing_, b.seen_traversing_) << i;
    ASSERT_EQ(a.halt_release_, b.halt_release_) << i;
    ASSERT_EQ(a.RejectTask, b.RejectTask) << i;
    ASSERT_EQ(a.IntermediateStop, b.IntermediateStop) << i;
    ASSERT_EQ(a.JogRequest1, b.JogRequest1) << i;
    ASSERT_EQ(a.StopActive, b.StopActive) << i;
    ASSERT_EQ(a.reset_phase_, b.reset_phase_) << i;
    ASSERT_EQ(a.reset_err_, b.reset_err_) << i;
    ASSERT_EQ(a.reset_scans_, b.reset_scans_) << i;
    ASSERT_EQ(a.reset_answered_, b.reset_answered_) << i;
    ASSERT_EQ(a.AckRequest, b.AckRequest) << i;
    ASSERT_EQ(a.ZSW1.value, b.ZSW1.value) << i;
    ASSERT_EQ(a.ZSW2.value, b.ZSW2.value) << i;
    ASSERT_EQ(a.XIST_A, b.XIST_A) << i;
    ASSERT_EQ(a.prev_xist_, b.prev_xist_) << i;
    ASSERT_EQ(a.have_prev_xist_, b.have_prev_xist_) << i;
    ASSERT_EQ(a.begun_, b.begun_) << i;
    ASSERT_EQ(a.last_cycle_, b.last_cycle_) << i;
    ASSERT_EQ(a.now_, b.now_) << i;
  }
  EXPECT_GT(quiet, 10000);  // the common case came often
}

}  // namespace
}  // namespace plc::drive
