#include "plc/fb/drive/drive_axis.hpp"

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <utility>

#include "plc/fb/drive/scaling.hpp"
#include "plc/fb/drive/sign_of_life.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace plc::drive {

namespace {

// The bits of a status or control word that its structure keeps (from()
// drops reserved bits, word() sends 0 in them).
template <class W>
constexpr std::uint16_t kept_bits = W::from(0xFFFF).word();

// Whether W::from(w).word() is w with the reserved bits cleared, for every
// w: then a word is taken or sent as that mask, without building the
// structure of named bits (the telegram 111 path of begin() and commit(),
// once per scan and per MC block).
template <class W>
constexpr bool round_trip_is_mask(std::uint32_t first, std::uint32_t count) {
  for (std::uint32_t w = first; w < first + count; ++w)
    if (W::from(static_cast<std::uint16_t>(w)).word() != (w & kept_bits<W>)) return false;
  return true;
}

// All 65,536 words, checked in 16 blocks of 4,096: each static_assert is
// its own constant evaluation, and clang stops one after about a million
// steps (-fconstexpr-steps), which a whole word type's 65,536 exceed.
constexpr std::uint32_t kMaskBlock = 4096;
template <class W, std::uint32_t Block>
struct MaskBlockChecked {
  static_assert(round_trip_is_mask<W>(Block * kMaskBlock, kMaskBlock));
  static constexpr bool value = true;
};
template <class W, std::uint32_t... Blocks>
constexpr bool every_block_checked(std::integer_sequence<std::uint32_t, Blocks...>) {
  return (MaskBlockChecked<W, Blocks>::value && ...);
}
template <class W>
constexpr bool round_trip_is_mask_everywhere =
    every_block_checked<W>(std::make_integer_sequence<std::uint32_t, 0x10000 / kMaskBlock>{});

static_assert(round_trip_is_mask_everywhere<Zsw1Pos>);
static_assert(round_trip_is_mask_everywhere<PosZsw1>);
static_assert(round_trip_is_mask_everywhere<PosZsw2>);
static_assert(round_trip_is_mask_everywhere<Zsw2>);
static_assert(round_trip_is_mask_everywhere<Meldw>);
static_assert(round_trip_is_mask_everywhere<Stw1Pos>);
static_assert(round_trip_is_mask_everywhere<PosStw1>);
static_assert(round_trip_is_mask_everywhere<PosStw2>);
static_assert(round_trip_is_mask_everywhere<Stw2>);

// commit()'s test of the four task requests (JogRequest1, JogRequest2,
// IntermediateStop, RejectTask): one byte each in a row, read as one word
// of the axis' bytes; 0 when all four are FALSE. offsetof on a class that
// is not standard-layout (DevicePort has private members), which GCC and
// Clang compute as for any class without virtual bases.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Winvalid-offsetof"
#endif
constexpr std::size_t kTaskRequestsOffset = offsetof(DriveAxis, JogRequest1);
static_assert(sizeof(DriveAxis::JogRequest1) == 1 && sizeof(DriveAxis::JogRequest2) == 1 &&
              sizeof(DriveAxis::IntermediateStop) == 1 && sizeof(DriveAxis::RejectTask) == 1);
static_assert(offsetof(DriveAxis, JogRequest2) == kTaskRequestsOffset + 1);
static_assert(offsetof(DriveAxis, IntermediateStop) == kTaskRequestsOffset + 2);
static_assert(offsetof(DriveAxis, RejectTask) == kTaskRequestsOffset + 3);
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
inline std::uint32_t task_requests(const DriveAxis& a) {
  std::uint32_t r;
  std::memcpy(&r, reinterpret_cast<const unsigned char*>(&a) + kTaskRequestsOffset, sizeof r);
  return r;
}

// The telegram 3 and 9 reads of begin_scan(), out of line: the telegram 111
// path (the E1's own, every scan) then needs fewer registers and no stack
// frame for the decoded structures.
[[gnu::noinline]] void read_standard3(DriveAxis& a, std::span<const std::uint8_t> in) {
  const auto t = Telegram3In::decode(in);
  a.ZSW1 = t.zsw1.word();
  a.NIST_B = t.nist_b;
  a.ZSW2 = t.zsw2.word(false);
  a.G1_ZSW = t.g1_zsw.word();
  a.G1_XIST1 = t.g1_xist1;
  a.G1_XIST2 = t.g1_xist2;
  a.ActPosition = static_cast<double>(static_cast<std::int32_t>(t.g1_xist1));
  a.ActVelocity = rpm_to_cu_per_s(nist_b_to_speed(a.NIST_B, a.RefSpeedRpm), a.CuPerRev);
}

[[gnu::noinline]] void read_standard9(DriveAxis& a, std::span<const std::uint8_t> in, TIME dt) {
  const auto t = Telegram9In::decode(in);
  a.ZSW1 = t.zsw1.word();
  a.AKTSATZ = t.aktsatz.word();
  a.ZSW2 = t.zsw2.word();
  a.XIST_A = t.xist_a;
  a.ActPosition = a.XIST_A;
  const double secs = std::chrono::duration<double>(dt).count();
  if (a.have_prev_xist_ && secs > 0)
    a.ActVelocity =
        static_cast<double>(static_cast<std::int32_t>(static_cast<std::uint32_t>(a.XIST_A) -
                                                      static_cast<std::uint32_t>(a.prev_xist_))) /
        secs;
}

// begin_scan()'s reads on telegrams 3 and 9 (and the check of a telegram
// the axis does not know), out of line; whether the telegram's shape is
// right. Called before begin_scan() sets now_ to this scan's time.
[[gnu::noinline]] bool read_standard(DriveAxis& a, std::span<const std::uint8_t> in, TIME now) {
  const auto tg = a.telegram();
  if (!is_supported_telegram(a.Telegram) || in.size() < in_bytes(tg) ||
      a.Port.out().size() < out_bytes(tg))
    return false;
  if (tg == TelegramType::Standard3)
    read_standard3(a, in);
  else
    read_standard9(a, in, a.begun_ ? now - a.now_ : TIME{});
  a.prev_xist_ = a.XIST_A;
  a.have_prev_xist_ = true;
  return true;
}

// Where read_hiwin111() stores several members at once: ZSW1, ZSW2,
// POS_ZSW1, POS_ZSW2 in a row (8 bytes), FAULT_CODE and WARN_CODE in a
// row (4 bytes). offsetof as for kTaskRequestsOffset.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Winvalid-offsetof"
#endif
constexpr std::size_t kStatusWordsOffset = offsetof(DriveAxis, ZSW1);
constexpr std::size_t kCodesOffset = offsetof(DriveAxis, FAULT_CODE);
static_assert(sizeof(DriveAxis::ZSW1) == 2 && sizeof(DriveAxis::ZSW2) == 2 &&
              sizeof(DriveAxis::POS_ZSW1) == 2 && sizeof(DriveAxis::POS_ZSW2) == 2 &&
              sizeof(DriveAxis::FAULT_CODE) == 2 && sizeof(DriveAxis::WARN_CODE) == 2);
static_assert(offsetof(DriveAxis, ZSW2) == kStatusWordsOffset + 2);
static_assert(offsetof(DriveAxis, POS_ZSW1) == kStatusWordsOffset + 4);
static_assert(offsetof(DriveAxis, POS_ZSW2) == kStatusWordsOffset + 6);
static_assert(offsetof(DriveAxis, WARN_CODE) == kCodesOffset + 2);
// commit()'s setpoint pairs: MDI_TARPOS, MDI_VELOCITY in a row (8 bytes),
// MDI_ACC, MDI_DEC in a row (4 bytes).
constexpr std::size_t kSetpointsOffset = offsetof(DriveAxis, MDI_TARPOS);
constexpr std::size_t kRampsOffset = offsetof(DriveAxis, MDI_ACC);
static_assert(sizeof(DriveAxis::MDI_TARPOS) == 4 && sizeof(DriveAxis::MDI_VELOCITY) == 4 &&
              sizeof(DriveAxis::MDI_ACC) == 2 && sizeof(DriveAxis::MDI_DEC) == 2);
static_assert(offsetof(DriveAxis, MDI_VELOCITY) == kSetpointsOffset + 4);
static_assert(offsetof(DriveAxis, MDI_DEC) == kRampsOffset + 2);
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
static_assert(std::endian::native == std::endian::little);

// Telegram111In::decode, the words as masks (round_trip_is_mask above):
// the same values as a word-by-word read, with fewer instructions. With
// SSE2 (every x86-64) PZD1..5 are swapped to host order together, put in
// the members' order (ZSW1, ZSW2, POS_ZSW1, POS_ZSW2: PZD 1, 4, 2, 3) and
// masked, and the four stored as one 8-byte word; FAULT_CODE and WARN_CODE
// (PZD10..11) are one big-endian 32-bit read, halves swapped into the
// members' order. Table3_2_2.Telegram111ReadEqualsDecodeOfEveryField
// (test_axis_wire.cpp) compares every field with Telegram111In::decode
// over random telegrams.
[[gnu::always_inline]] inline void read_hiwin111(DriveAxis& a, std::span<const std::uint8_t> in) {
  using T = Telegram111In;
  auto* const bytes = reinterpret_cast<unsigned char*>(&a);
#if defined(__SSE2__)
  static_assert(T::kZsw1 == 0 && T::kPosZsw1 == 2 && T::kPosZsw2 == 4 && T::kZsw2 == 6 &&
                T::kMeldw == 8 && T::kBytes >= 16);
  __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in.data()));  // PZD1..8
  v = _mm_or_si128(_mm_srli_epi16(v, 8), _mm_slli_epi16(v, 8));
  v = _mm_shufflelo_epi16(v, _MM_SHUFFLE(2, 1, 3, 0));  // lanes: PZD1, 4, 2, 3, then 5..8
  v = _mm_and_si128(
      v,
      _mm_setr_epi16(static_cast<short>(kept_bits<Zsw1Pos>), static_cast<short>(kept_bits<Zsw2>),
                     static_cast<short>(kept_bits<PosZsw1>), static_cast<short>(kept_bits<PosZsw2>),
                     static_cast<short>(kept_bits<Meldw>), 0, 0, 0));
  _mm_storel_epi64(reinterpret_cast<__m128i*>(bytes + kStatusWordsOffset), v);
  a.MELDW = static_cast<std::uint16_t>(_mm_extract_epi16(v, 4));
#else
  a.ZSW1 = static_cast<std::uint16_t>(wire::u16(in, T::kZsw1) & kept_bits<Zsw1Pos>);
  a.POS_ZSW1 = static_cast<std::uint16_t>(wire::u16(in, T::kPosZsw1) & kept_bits<PosZsw1>);
  a.POS_ZSW2 = static_cast<std::uint16_t>(wire::u16(in, T::kPosZsw2) & kept_bits<PosZsw2>);
  a.ZSW2 = static_cast<std::uint16_t>(wire::u16(in, T::kZsw2) & kept_bits<Zsw2>);
  a.MELDW = static_cast<std::uint16_t>(wire::u16(in, T::kMeldw) & kept_bits<Meldw>);
#endif
  const std::int32_t xist_a = wire::i32(in, T::kXistA);
  const std::int32_t nist_b = wire::i32(in, T::kNistB);
  static_assert(T::kWarnCode == T::kFaultCode + 2);
  const std::uint32_t codes = std::rotl(wire::u32(in, T::kFaultCode), 16);  // FAULT | WARN << 16
  a.XIST_A = xist_a;
  a.NIST_B = nist_b;
  std::memcpy(bytes + kCodesOffset, &codes, sizeof codes);
  a.ActPosition = xist_a;
  a.ActVelocity = rpm_to_cu_per_s(nist_b_to_speed(nist_b, a.RefSpeedRpm), a.CuPerRev);
}

// update_state()'s work, always inline: begin_scan() runs it every scan
// (as a call it was a tail call that reloaded what begin_scan() had just
// computed); update_state() stays for the blocks that call it.
[[gnu::always_inline]] inline void update_state_of(DriveAxis& a) {
  const std::uint16_t e = a.axis_error();
  if (e) {
    if (a.State != AxisState::ErrorStop) a.abort_all();
    a.latch_error(e);
    a.State = AxisState::ErrorStop;
    a.RestartInhibit = true;  // no restart without an explicit reset
    return;
  }
  if (a.State == AxisState::ErrorStop) return;  // until MC_Reset clears error_
  if (!a.operation_enabled()) {
    if (a.State != AxisState::Disabled) a.abort_all();
    a.State = AxisState::Disabled;
    return;
  }
  const bool running = a.phase_ == DriveAxis::Phase::PreLow ||
                       a.phase_ == DriveAxis::Phase::Request ||
                       a.phase_ == DriveAxis::Phase::Running;
  // Every state below but Standstill needs StopActive or a running command:
  // without both (a powered axis at rest, most scans) it is Standstill at
  // once, without asking the command's kind.
  if (!a.StopActive && !running) {
    a.State = AxisState::Standstill;
  } else if (a.StopActive || (a.kind_ == DriveAxis::Kind::Stop && running)) {
    a.State = AxisState::Stopping;
  } else if (a.kind_ == DriveAxis::Kind::Homing && running) {
    a.State = AxisState::Homing;
  } else if (a.kind_ == DriveAxis::Kind::Task && running) {
    a.State = a.task_kind_ == TaskKind::Velocity ? AxisState::ContinuousMotion
                                                 : AxisState::DiscreteMotion;
  } else if (a.kind_ == DriveAxis::Kind::Halt && running) {
    a.State = AxisState::DiscreteMotion;
  } else if (a.kind_ == DriveAxis::Kind::Jog && running) {
    a.State = AxisState::ContinuousMotion;
  } else {
    a.State = AxisState::Standstill;
  }
}

}  // namespace

const char* to_string(AxisState s) {
  switch (s) {
    case AxisState::Disabled:
      return "Disabled";
    case AxisState::Standstill:
      return "Standstill";
    case AxisState::Homing:
      return "Homing";
    case AxisState::DiscreteMotion:
      return "DiscreteMotion";
    case AxisState::ContinuousMotion:
      return "ContinuousMotion";
    case AxisState::SynchronizedMotion:
      return "SynchronizedMotion";
    case AxisState::Stopping:
      return "Stopping";
    case AxisState::ErrorStop:
      return "ErrorStop";
  }
  return "?";
}

DriveState drive_state_from_zsw1(std::uint16_t z) {
  if (z & Zsw1Pos::kFault) return DriveState::Fault;
  if (z & Zsw1Pos::kSwitchOnInhibited) return DriveState::SwitchingOnInhibited;
  if (z & Zsw1Pos::kOperationEnabled) return DriveState::Operation;
  if ((z & Zsw1Pos::kReadyToOperate) && (z & Zsw1Pos::kReadyToSwitchOn))
    return DriveState::SwitchedOn;
  if (z & Zsw1Pos::kReadyToSwitchOn) {
    // S2 and the OFF1 branch of S5 show the same bits 0-2; S5 has the
    // pulses on, which ZSW1 alone does not tell, so report S2.
    return DriveState::ReadyForSwitchingOn;
  }
  return DriveState::SwitchingOff;  // OFF3 branch: bits 0-2 = 0, bit 6 = 0
}

namespace {

// begin_scan()'s watch of the drive's sign-of-life and its communication
// error, once the telegram was read (or found of the wrong shape).
[[gnu::always_inline]] inline void watch_communication(DriveAxis& a, bool shape_ok, bool online) {
  // Drive sign-of-life: the counter must move; standing still for more
  // than SignOfLifeTolerance scans is a loss (latched until a reset, or
  // until the device goes offline). An offline device has no counter to
  // watch, and the connection after it counts anew: monitoring starts again
  // from its first non-zero value (spec §10.1), as the drive does with ours.
  // The loss stays latched as the axis error (ErrorStop) until a reset.
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
  // Not bound: offline; a wrong telegram shape; not online: offline; a
  // lost sign-of-life; else none. An online port is bound, so the common
  // case (online, right shape) asks only the sign-of-life.
  if (online && shape_ok)
    a.CommError = a.SignOfLifeLost ? kErrSignOfLife : 0;
  else
    a.CommError = !a.Port.bound() || shape_ok ? kErrOffline : kErrTelegram;
  a.CommOk = a.CommError == 0;
  a.sol_out_ = next_sign_of_life(a.sol_out_);
}

// begin_scan()'s last part: the command's and the reset's handshakes, then
// the axis state. advance() acts only in a command's running phases (and
// on a halt's release after Done), advance_reset() only during a reset: in
// the other scans (most) both return at once, so they are not called.
[[gnu::always_inline]] inline void advance_and_update(DriveAxis& a) {
  using Phase = DriveAxis::Phase;
  using Kind = DriveAxis::Kind;
  using ResetPhase = DriveAxis::ResetPhase;
  const bool running =
      a.phase_ == Phase::PreLow || a.phase_ == Phase::Request || a.phase_ == Phase::Running;
  if (a.kind_ != Kind::None && (running || (a.kind_ == Kind::Halt && a.phase_ == Phase::Done)))
    a.advance();
  if (a.reset_phase_ == ResetPhase::AckLow || a.reset_phase_ == ResetPhase::AckHigh)
    a.advance_reset();
  update_state_of(a);
}

// Out of line, for begin_scan() to jump to (a tail call, no frame of its own):
// the scans with a command or a reset to advance, or with a state other
// than a quiet Standstill to keep.
[[gnu::noinline]] void advance_and_update_out_of_line(DriveAxis& a) { advance_and_update(a); }
[[gnu::noinline]] void update_state_out_of_line(DriveAxis& a) { update_state_of(a); }

// begin_scan() on telegrams 3 and 9 (and a telegram the axis does not
// know), out of line: the read needs the last scan's now_ (read_standard()).
[[gnu::noinline]] void begin_scan_standard(DriveAxis& a, const ScanContext& ctx) {
  const bool shape_ok = read_standard(a, a.Port.in(), ctx.now);
  a.begun_ = true;
  a.last_cycle_ = ctx.cycle;
  a.now_ = ctx.now;
  watch_communication(a, shape_ok, a.Port.online());
  advance_and_update(a);
}

}  // namespace

void DriveAxis::begin_scan(const ScanContext& ctx) {
  // Telegram 111 (the E1's) asked first and read here; the others out of
  // line. Every call out of this path is a tail call, so it needs no
  // frame of its own.
  if (telegram() != TelegramType::Hiwin111) {
    begin_scan_standard(*this, ctx);
    return;
  }
  const auto in = Port.in();
  const bool shape_ok = in.size() >= in_bytes(TelegramType::Hiwin111) &&
                        Port.out().size() >= out_bytes(TelegramType::Hiwin111);
  if (shape_ok) {
    read_hiwin111(*this, in);
    prev_xist_ = XIST_A;
    have_prev_xist_ = true;
  }
  begun_ = true;
  last_cycle_ = ctx.cycle;
  now_ = ctx.now;
  watch_communication(*this, shape_ok, Port.online());

  // A command in a running phase (or a halt's release after Done) or a
  // reset to advance: the whole way, out of line. A running phase without
  // a command (kind_ None: nothing to advance) goes there too, as
  // advance_and_update() then does only what update_state_of() does.
  const bool running =
      phase_ == Phase::PreLow || phase_ == Phase::Request || phase_ == Phase::Running;
  if (running || (kind_ == Kind::Halt && phase_ == Phase::Done) ||
      reset_phase_ == ResetPhase::AckLow || reset_phase_ == ResetPhase::AckHigh) {
    advance_and_update_out_of_line(*this);
    return;
  }
  // Nothing to advance and nothing running. update_state_of() leaves a
  // powered axis without an error or StopActive (most scans) in
  // Standstill; any other case takes its whole way.
  if (axis_error() || State == AxisState::ErrorStop || !operation_enabled() || StopActive) {
    update_state_out_of_line(*this);
    return;
  }
  State = AxisState::Standstill;
}

void DriveAxis::abort_all() {
  if (kind_ != Kind::None && phase_ != Phase::Done && phase_ != Phase::Error)
    phase_ = Phase::Aborted;
  kind_ = Kind::None;
  stw6_ = false;
  homing_bit_ = false;
  JogRequest1 = JogRequest2 = false;
  IntermediateStop = RejectTask = false;
  StopActive = false;
  SetReferenceRequest = false;
}

void DriveAxis::reset_errors() {
  error_ = 0;
  if (State == AxisState::ErrorStop) State = AxisState::Disabled;  // update_state() refines
  SignOfLifeLost = false;
  sol_seen_ = false;
  sol_stall_ = 0;
}

void DriveAxis::start_reset(TIME timeout) {
  // The monitoring starts again; a loss stays latched in error_ (ErrorStop)
  // until the reset is done.
  SignOfLifeLost = false;
  sol_seen_ = false;
  sol_stall_ = 0;
  AckRequest = false;  // this scan sends STW1.7 = 0: the drive needs 0 -> 1
  reset_phase_ = ResetPhase::AckLow;
  reset_start_ = now_;
  reset_timeout_ = timeout;
  reset_scans_ = 0;
  reset_err_ = 0;
  reset_sol_ = drive_sign_of_life();
  reset_answered_ = false;
}

DriveAxis::ResetStatus DriveAxis::reset_status() const {
  switch (reset_phase_) {
    case ResetPhase::Idle:
      return ResetStatus::Idle;
    case ResetPhase::Done:
      return ResetStatus::Done;
    case ResetPhase::Error:
      return ResetStatus::Error;
    default:
      return ResetStatus::Busy;
  }
}

// Once per scan, after the inputs were read. STW1.7 is an edge for the
// drive (spec §4.2, §10.2: a PLC that holds it at 1 acknowledges no later
// fault), so every request sends 0 first, for as long as the drive needs
// to see it: until the drive has answered since (its sign-of-life moved,
// one exchange in lockstep, more on a slower bus), or SignOfLifeTolerance
// scans where the counter is not watched or stands still. Then 1 until the
// drive reports no fault (it has seen the edge), then 0 again.
void DriveAxis::advance_reset() {
  if (reset_phase_ != ResetPhase::AckLow && reset_phase_ != ResetPhase::AckHigh) return;
  if (!SignOfLifeCheck || drive_sign_of_life() != reset_sol_) reset_answered_ = true;
  if (reset_scans_ < 0xFFFF) ++reset_scans_;
  if (reset_phase_ == ResetPhase::AckLow) {
    if (!reset_answered_ && reset_scans_ <= SignOfLifeTolerance) return;
    reset_phase_ = ResetPhase::AckHigh;
  }
  // Done only on a drive that answers: no fault, communication good, and
  // its sign-of-life moved since the request (a stalled counter looks good
  // for SignOfLifeTolerance scans after the monitoring restarted).
  if (CommOk && !drive_fault() && reset_answered_) {
    AckRequest = false;
    reset_phase_ = ResetPhase::Done;
    reset_errors();
    if (!RequireEnableEdgeAfterReset) RestartInhibit = false;
  } else if (now_ - reset_start_ > reset_timeout_) {
    AckRequest = false;
    reset_phase_ = ResetPhase::Error;
    reset_err_ = drive_fault() ? kErrResetTimeout : CommError ? CommError.value : kErrSignOfLife;
  } else {
    AckRequest = true;
  }
}

void DriveAxis::update_state() { update_state_of(*this); }

// The handshakes of the command in control, once per scan.
void DriveAxis::advance() {
  const bool ack = (ZSW1 & Zsw1Pos::kTaskAck) != 0;
  const bool fail_allowed = CommOk;
  auto fail = [&](std::uint16_t e) {
    cmd_err_ = e;
    phase_ = Phase::Error;
    stw6_ = false;
    homing_bit_ = false;
  };
  switch (kind_) {
    case Kind::None:
      break;
    case Kind::Task:
      if (phase_ == Phase::PreLow) {
        stw6_ = false;
        if (!stw6_sent_ && !ack) {
          phase_ = Phase::Request;
          phase_start_ = now_;
          stw6_ = true;
        } else if (fail_allowed && now_ - phase_start_ > AckTimeout) {
          fail(kErrTaskNotAck);
        }
      } else if (phase_ == Phase::Request) {
        stw6_ = true;
        if (ack && stw6_sent_) {
          phase_ = Phase::Running;
          stw6_ = false;
          seen_traversing_ = (POS_ZSW2 & PosZsw2::kTraversingActive) != 0;
          if (task_kind_ != TaskKind::Velocity && target_reached()) phase_ = Phase::Done;
        } else if (fail_allowed && now_ - phase_start_ > AckTimeout) {
          fail(kErrTaskNotAck);
        }
      } else if (phase_ == Phase::Running) {
        stw6_ = false;
        const bool traversing = (POS_ZSW2 & PosZsw2::kTraversingActive) != 0;
        if (traversing) seen_traversing_ = true;
        if (task_kind_ != TaskKind::Velocity && target_reached() && !traversing) {
          phase_ = Phase::Done;
        } else if (Telegram == 111 && seen_traversing_ && !traversing && !IntermediateStop &&
                   !target_reached() && standstill()) {
          fail(kErrTaskCancelled);  // the drive dropped the task (overtravel, ...)
        }
      }
      break;
    case Kind::Homing:
      if (phase_ == Phase::Running) {
        homing_bit_ = true;
        const bool active = (POS_ZSW1 & PosZsw1::kHomingActive) != 0;
        if (!homing_started_ && (!homed() || active)) homing_started_ = true;
        if (homing_started_ && homed() && !active && standstill()) {
          phase_ = Phase::Done;
          homing_bit_ = false;
        } else if (fail_allowed && now_ - phase_start_ > homing_timeout_) {
          fail(kErrHomingTimeout);
        }
      }
      break;
    case Kind::Stop:
      if (phase_ == Phase::Running && standstill()) phase_ = Phase::Done;
      break;
    case Kind::Halt:
      if (phase_ == Phase::Running && standstill()) {
        RejectTask = true;  // the paused task is dropped at standstill
        halt_release_ = true;
        phase_ = Phase::Done;
      } else if (phase_ == Phase::Done && halt_release_) {
        RejectTask = false;
        IntermediateStop = false;
        halt_release_ = false;
      }
      break;
    case Kind::Jog:
      if (phase_ == Phase::Running && !JogRequest1 && !JogRequest2 && standstill())
        phase_ = Phase::Done;
      break;
  }
}

// Every command starts the same way: the previous one is aborted, the new
// one gets the next id and starts its first phase now.
void DriveAxis::open_command(Kind kind, Phase phase) {
  abort_all();
  cmd_id_ = next_id_++;
  kind_ = kind;
  cmd_err_ = 0;
  phase_ = phase;
  phase_start_ = now_;
}

std::uint32_t DriveAxis::start_task(TaskKind kind, DINT position, DINT mdi_velocity, INT mdi_acc,
                                    INT mdi_dec) {
  open_command(Kind::Task, Phase::PreLow);
  task_kind_ = kind;
  seen_traversing_ = false;
  MDI_TARPOS = kind == TaskKind::Velocity ? (position < 0 ? -0x7FFFFFFF : 0x7FFFFFFF) : position;
  MDI_VELOCITY = mdi_velocity;
  task_velocity_ = mdi_velocity;
  MDI_ACC = mdi_acc;
  MDI_DEC = mdi_dec;
  MDI_MODE = kind == TaskKind::Absolute ? MdiMode::kAbsolute : 0;
  advance();
  return cmd_id_;
}

std::uint32_t DriveAxis::start_homing(TIME timeout) {
  open_command(Kind::Homing, Phase::Running);
  homing_timeout_ = timeout;
  homing_started_ = false;
  homing_bit_ = true;
  return cmd_id_;
}

std::uint32_t DriveAxis::start_stop() {
  open_command(Kind::Stop, Phase::Running);
  RejectTask = true;
  StopActive = true;
  return cmd_id_;
}

void DriveAxis::end_stop(std::uint32_t id) {
  if (id != cmd_id_) return;
  StopActive = false;
  RejectTask = false;
}

std::uint32_t DriveAxis::start_halt() {
  open_command(Kind::Halt, Phase::Running);
  IntermediateStop = true;
  halt_release_ = false;
  return cmd_id_;
}

std::uint32_t DriveAxis::start_jog() {
  const bool j1 = JogRequest1, j2 = JogRequest2;
  open_command(Kind::Jog, Phase::Running);
  JogRequest1 = j1;
  JogRequest2 = j2;
  return cmd_id_;
}

void DriveAxis::release(std::uint32_t id) {
  if (id != cmd_id_) return;
  if (kind_ == Kind::Jog) JogRequest1 = JogRequest2 = false;
}

CmdStatus DriveAxis::status(std::uint32_t id) const {
  if (id == 0 || id != cmd_id_) return CmdStatus::Aborted;
  switch (phase_) {
    case Phase::Done:
      return CmdStatus::Done;
    case Phase::Error:
      return CmdStatus::Error;
    case Phase::Aborted:
    case Phase::Idle:
      return CmdStatus::Aborted;
    default:
      return CmdStatus::Busy;
  }
}

std::uint16_t DriveAxis::cmd_error(std::uint32_t id) const {
  return id == cmd_id_ && phase_ == Phase::Error ? cmd_err_ : std::uint16_t{0};
}

bool DriveAxis::in_velocity(std::uint32_t id) const {
  if (id != cmd_id_ || kind_ != Kind::Task || phase_ != Phase::Running) return false;
  const double want =
      mdi_velocity_to_cu_per_s(task_velocity_) * override_to_percent(OVERRIDE) / 100.0;
  const double tol = std::max(0.01 * want, mdi_velocity_to_cu_per_s(1));
  return std::fabs(std::fabs(ActVelocity) - want) <= tol;
}

namespace {

// STW1's power and acknowledge bits (and kControlByPlc), as every
// telegram sends them; `power` tells whether power is asked for. Ends
// RestartInhibit on a withdrawn power request (below).
[[gnu::always_inline]] inline std::uint16_t power_bits(DriveAxis& a, bool& power) {
  std::uint16_t stw1 = Stw1Pos::kControlByPlc;
  // A withdrawn power request ends the inhibit once the error is cleared
  // (the next request is a new Enable edge); an explicit reset ends it in
  // advance_reset() (header comment).
  if (a.RestartInhibit && a.State != AxisState::ErrorStop && !a.PowerRequest)
    a.RestartInhibit = false;
  power = a.CommOk && a.PowerRequest && !a.InhibitPower && !a.drive_fault() && !a.RestartInhibit &&
          a.State != AxisState::ErrorStop;
  if (power) {
    stw1 |= Stw1Pos::kNoCoastStop | Stw1Pos::kNoQuickStop | Stw1Pos::kEnableOperation;
    // From S1 the drive needs ON = 0 first (S1 -> S2), then ON = 1.
    if (!(a.ZSW1 & Zsw1Pos::kSwitchOnInhibited)) stw1 |= Stw1Pos::kOn;
  } else {
    const StopMode m = a.CommOk && !a.InhibitPower ? a.PowerStopMode : StopMode::Off1Ramp;
    if (m != StopMode::Off2Coast) stw1 |= Stw1Pos::kNoCoastStop;
    if (m != StopMode::Off3Quick) stw1 |= Stw1Pos::kNoQuickStop;
  }
  if (a.AckRequest) stw1 |= Stw1Pos::kFaultAck;
  return stw1;
}

// STW1's traversing-task bits (telegrams 9 and 111).
[[gnu::always_inline]] inline std::uint16_t task_bits(const DriveAxis& a, std::uint16_t stw1) {
  // The four task requests JogRequest1, JogRequest2, IntermediateStop and
  // RejectTask, one byte each in a row (static_asserts at the top): all
  // FALSE (most scans) is one test of the four bytes, whose bits are then
  // those of !RejectTask and !IntermediateStop.
  if (task_requests(a) == 0) {
    stw1 |= Stw1Pos::kNoRejectTask | Stw1Pos::kNoIntermediateStop;
  } else {
    if (!a.RejectTask) stw1 |= Stw1Pos::kNoRejectTask;
    if (!a.IntermediateStop) stw1 |= Stw1Pos::kNoIntermediateStop;
    if (a.JogRequest1) stw1 |= Stw1Pos::kJog1;
    if (a.JogRequest2) stw1 |= Stw1Pos::kJog2;
  }
  if (a.stw6_) stw1 |= Stw1Pos::kActivateTask;
  if (a.homing_bit_) stw1 |= Stw1Pos::kStartHoming;
  return stw1;
}

// POS_STW1: MDI active, absolute as MDI_MODE's bit (shifted into place
// rather than chosen by a branch: the same word).
static_assert(PosStw1::kAbsolute == MdiMode::kAbsolute << 8);
[[gnu::always_inline]] inline std::uint16_t pos_stw1_of(const DriveAxis& a) {
  return static_cast<std::uint16_t>(PosStw1::kActivateMdi | (a.MDI_MODE & MdiMode::kAbsolute) << 8);
}
[[gnu::always_inline]] inline std::uint16_t pos_stw2_of(const DriveAxis& a) {
  return static_cast<std::uint16_t>(a.SetReferenceRequest ? PosStw2::kSetReferencePoint : 0);
}

// commit() on telegrams 3 and 9 (and a telegram the axis does not know),
// out of line: the telegram 111 path (the E1's own, every scan) then keeps
// fewer values in registers.
[[gnu::noinline]] void commit_standard(DriveAxis& a, std::span<std::uint8_t> out) {
  const auto tg = a.telegram();
  if (!is_supported_telegram(a.Telegram) || out.size() < out_bytes(tg)) return;
  bool power = false;
  std::uint16_t stw1 = power_bits(a, power);
  a.STW2 = static_cast<std::uint16_t>(a.sol_out_ << 12);
  if (tg == TelegramType::Standard3) {
    a.STW1 = static_cast<std::uint16_t>(stw1 & Stw1Speed::kDefined);
    Telegram3Out t;
    t.stw1 = Stw1Speed::from(a.STW1);
    t.nsoll_b = power ? a.NSOLL_B : 0;
    t.stw2 = Stw2::from(a.STW2);
    t.g1_stw = G1Stw::from(a.G1_STW);
    t.encode(out);
    return;
  }
  stw1 = task_bits(a, stw1);
  a.STW1 = stw1;
  a.stw6_sent_ = a.stw6_;
  a.POS_STW1 = pos_stw1_of(a);
  a.POS_STW2 = pos_stw2_of(a);
  a.SATZANW = Satzanw::kActivateMdi;
  Telegram9Out t;
  t.stw1 = Stw1Pos::from(a.STW1);
  t.satzanw = Satzanw::from(a.SATZANW);
  t.stw2 = Stw2::from(a.STW2);
  t.mdi_tarpos = a.MDI_TARPOS;
  t.mdi_velocity = a.MDI_VELOCITY;
  t.mdi_acc = a.MDI_ACC;
  t.mdi_dec = a.MDI_DEC;
  t.mdi_mode = MdiMode::from(a.MDI_MODE);
  t.encode(out);
}

}  // namespace

void DriveAxis::commit() {
  const auto out = Port.out();
  // Telegram 111 asked first, as in begin_scan().
  if (telegram() != TelegramType::Hiwin111) {
    commit_standard(*this, out);
    return;
  }
  if (out.size() < out_bytes(TelegramType::Hiwin111)) return;
  bool power = false;
  const std::uint16_t stw1 = task_bits(*this, power_bits(*this, power));
  const auto stw2 = static_cast<std::uint16_t>(sol_out_ << 12);
  const bool stw6 = stw6_;
  const std::uint16_t pos_stw1 = pos_stw1_of(*this);
  const std::uint16_t pos_stw2 = pos_stw2_of(*this);
  // Telegram111Out::encode, the words as masks. The control words are sent
  // from the values just composed (for the compiler the bytes may alias any
  // member: it would load each word again after a store), each kept in its
  // member next to its store (so that the compiler does not merge the four
  // stores into one word built with shifts, more instructions than the
  // stores); the setpoints are read after them, as before, each once.
  using T = Telegram111Out;
  STW1 = stw1;
  wire::put16(out, T::kStw1, static_cast<std::uint16_t>(stw1 & kept_bits<Stw1Pos>));
  POS_STW1 = pos_stw1;
  wire::put16(out, T::kPosStw1, static_cast<std::uint16_t>(pos_stw1 & kept_bits<PosStw1>));
  POS_STW2 = pos_stw2;
  wire::put16(out, T::kPosStw2, static_cast<std::uint16_t>(pos_stw2 & kept_bits<PosStw2>));
  STW2 = stw2;
  wire::put16(out, T::kStw2, static_cast<std::uint16_t>(stw2 & kept_bits<Stw2>));
  stw6_sent_ = stw6;
  SATZANW = Satzanw::kActivateMdi;
  wire::put16(out, T::kOverride, OVERRIDE);
  // MDI_TARPOS and MDI_VELOCITY (PZD6..9), MDI_ACC and MDI_DEC (PZD10..11)
  // lie in the same order in the axis and in the telegram: each pair is
  // read as one word and sent byte-swapped as one, its halves swapped back
  // into their places (the same bytes as two big-endian stores).
  const auto* const bytes = reinterpret_cast<const unsigned char*>(this);
  std::uint64_t tarpos_velocity;  // MDI_TARPOS | MDI_VELOCITY << 32
  std::memcpy(&tarpos_velocity, bytes + kSetpointsOffset, sizeof tarpos_velocity);
  std::uint32_t acc_dec;  // MDI_ACC | MDI_DEC << 16
  std::memcpy(&acc_dec, bytes + kRampsOffset, sizeof acc_dec);
  tarpos_velocity = std::rotl(__builtin_bswap64(tarpos_velocity), 32);
  acc_dec = std::rotl(__builtin_bswap32(acc_dec), 16);
  static_assert(T::kMdiVelocity == T::kMdiTarpos + 4 && T::kMdiDec == T::kMdiAcc + 2);
  std::memcpy(out.data() + T::kMdiTarpos, &tarpos_velocity, sizeof tarpos_velocity);
  std::memcpy(out.data() + T::kMdiAcc, &acc_dec, sizeof acc_dec);
  wire::put16(out, T::kReserved12, 0);
}

}  // namespace plc::drive
