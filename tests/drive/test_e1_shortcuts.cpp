// The E1 model's shortcuts (issue 23): the drive's telegram is encoded once
// per change of what it shows (only ZSW2's sign-of-life is put in every
// step), and a drive at rest with nothing to start skips the general motion
// update. A model with the shortcuts and one without them
// (set_shortcuts(false)) get the same PLC telegrams, faults, warnings and
// parameter writes for many steps in each telegram (3, 9, 111); their
// telegrams (Tables 3.1.1, 3.3.1, 3.4.1 of the spec: every byte) and their
// encoder position, position and speed (every bit) must be equal at every
// step. A shortcut that missed one of its inputs or conditions fails here.
// The calls besides the telegram also come while the words stand still, so
// that the rest repeat (a step that skips to the telegram copy after a step
// that changed nothing) must notice each of them.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/fb/drive/scaling.hpp"
#include "plc/fb/drive/sign_of_life.hpp"
#include "plc/fb/drive/telegrams.hpp"

namespace plc::sim {
namespace {

using namespace plc::drive;
using namespace std::chrono_literals;

void run_pair(TelegramType tg, std::uint32_t seed) {
  HiwinE1Config c;
  c.telegram = tg;
  c.neg_limit = -400000;  // overtravel reachable
  c.pos_limit = 400000;
  c.home_switch = 20000;
  c.following_error_limit = 150000;
  HiwinE1Model fast(c), full(c);
  full.set_shortcuts(false);
  std::vector<std::uint8_t> out(fast.output_size()), in_fast(fast.input_size()),
      in_full(full.input_size());
  std::mt19937 rng(seed);
  auto pick = [&rng](std::uint32_t n) { return static_cast<std::uint32_t>(rng() % n); };
  const std::size_t stw2 = tg == TelegramType::Standard3   ? Telegram3Out::kStw2
                           : tg == TelegramType::Standard9 ? Telegram9Out::kStw2
                                                           : Telegram111Out::kStw2;
  // Control words held for a while, so the drive gets to move and to stand.
  // (0x043F: S4; 0x047F: S4 with a task (STW1.6) or, telegram 3, the
  // setpoint enabled.)
  static constexpr std::array<std::uint16_t, 16> kStw1 = {
      0x043E,
      0x043F,
      0x043F,
      0x047F,
      0x047F,
      0x047F,
      0x043F | Stw1Pos::kJog1,
      0x043F | Stw1Pos::kJog2,
      0x043F | Stw1Pos::kStartHoming,
      0x045F,  // intermediate stop
      0x046F,  // reject task
      0x043D,  // OFF2
      0x043B,  // OFF3
      0x04BE,  // fault acknowledge
      0x003F,  // no control by PLC
      0x047E,
  };

  TIME now{};
  std::uint8_t sol = 0;
  int hold = 0, changed = 0, same = 0, repeats = 0, stall = 0, sol_faults = 0,
      sol_faults_at_rest = 0;
  std::vector<std::uint8_t> prev(in_fast.size());
  for (int step = 0; step < 200000; ++step) {
    if (hold-- <= 0) {
      hold = static_cast<int>(pick(400));
      std::uint16_t stw1 = kStw1[pick(kStw1.size())];
      if (pick(3) == 0) {  // new setpoints: random bytes behind STW1 and STW2
        for (auto& b : out) b = static_cast<std::uint8_t>(rng());
        if (tg == TelegramType::Hiwin111) {  // mostly sane MDI tasks
          io::store_be<std::uint32_t>(out, Telegram111Out::kMdiTarpos,
                                      static_cast<std::uint32_t>(pick(40000)) - 20000u);
          io::store_be<std::uint32_t>(out, Telegram111Out::kMdiVelocity, pick(400000));
          io::store_be<std::uint16_t>(out, Telegram111Out::kOverride,
                                      static_cast<std::uint16_t>(pick(0x6000)));
        }
      }
      io::store_be<std::uint16_t>(out, 0, stw1);
    }
    // Now and then something besides the telegram, mostly while the words
    // stand still.
    if (pick(300) == 0) {
      switch (pick(9)) {
        case 0:
          fast.trip_alarm(0xFB1);
          full.trip_alarm(0xFB1);
          break;
        case 1: {
          const std::uint16_t w = pick(2) ? 0x0123 : 0;
          fast.set_warning(w);
          full.set_warning(w);
          break;
        }
        case 2: {
          const double pt317 = 1000 + pick(4000);
          ASSERT_EQ(fast.set_parameter(pt_pnu(0x317), pt317),
                    full.set_parameter(pt_pnu(0x317), pt317));
          break;
        }
        case 3:
          fast.power_cycle();
          full.power_cycle();
          break;
        case 4: {
          const bool frozen = pick(2) == 0;
          fast.freeze_sign_of_life(frozen);
          full.freeze_sign_of_life(frozen);
          break;
        }
        case 5: {  // Pt534 (acceleration ramp) through the parameter channel
          ParamRequest rq;
          rq.request_id = 0x02;  // change value
          rq.pnu = pt_pnu(0x534);
          rq.format = 0x06;  // U16
          rq.num_values = 1;
          rq.values[0] = 2 + pick(300);
          std::array<std::uint8_t, 64> buf{};
          const std::span<const std::uint8_t> r(buf.data(), rq.encode(buf));
          EXPECT_EQ(fast.write_record(kParamRecordIndex, r),
                    full.write_record(kParamRecordIndex, r));
          std::array<std::uint8_t, 64> ans_fast{}, ans_full{};
          std::size_t n_fast = 0, n_full = 0;
          fast.read_record(kParamRecordIndex, ans_fast, n_fast);
          full.read_record(kParamRecordIndex, ans_full, n_full);
          EXPECT_EQ(ans_fast, ans_full);
          EXPECT_EQ(ans_fast[1], 0x02);  // a positive response: the value was written
          break;
        }
        default:
          break;
      }
    }
    const bool repeating = fast.rest_repeating();
    repeats += repeating;
    const bool was_fault = full.state() == HiwinE1Model::State::Fault;
    // Now and then the PLC's sign-of-life stands for a few steps: a short
    // stall is tolerated (PNU 925), a long one trips AL.FB1, also at rest.
    if (stall == 0 && pick(800) == 0) stall = 2 + static_cast<int>(pick(10));
    if (stall > 0) {
      --stall;
    } else {
      sol = next_sign_of_life(sol);
    }
    io::store_be<std::uint16_t>(out, stw2, static_cast<std::uint16_t>(sol << 12));
    now += 1ms;
    fast.step(now, 1ms, out, in_fast);
    full.step(now, 1ms, out, in_full);
    ASSERT_EQ(in_fast, in_full) << "telegram " << static_cast<int>(tg) << ", step " << step;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(fast.encoder_position()),
              std::bit_cast<std::uint64_t>(full.encoder_position()))
        << "telegram " << static_cast<int>(tg) << ", step " << step;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(fast.position()),
              std::bit_cast<std::uint64_t>(full.position()))
        << "telegram " << static_cast<int>(tg) << ", step " << step;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(fast.velocity()),
              std::bit_cast<std::uint64_t>(full.velocity()))
        << "telegram " << static_cast<int>(tg) << ", step " << step;
    ASSERT_EQ(fast.state(), full.state()) << "step " << step;
    ASSERT_EQ(fast.fault_code(), full.fault_code()) << "step " << step;
    const bool sol_fault = !was_fault && full.fault_code() == 0xFB1;
    sol_faults += sol_fault;
    sol_faults_at_rest += sol_fault && repeating;
    // The telegram but ZSW2 (sign-of-life): how often the cache was used.
    in_fast[Telegram111In::kZsw2] = in_fast[Telegram111In::kZsw2 + 1] = 0;
    in_fast[Telegram9In::kZsw2] = in_fast[Telegram9In::kZsw2 + 1] = 0;
    (in_fast == prev ? same : changed)++;
    prev = in_fast;
  }
  // Both paths ran many times: the drive moved and stood still.
  EXPECT_GT(changed, 5000) << static_cast<int>(tg);
  EXPECT_GT(same, 20000) << static_cast<int>(tg);
  if (tg == TelegramType::Hiwin111) {
    EXPECT_GT(repeats, 5000);
    EXPECT_GT(sol_faults_at_rest, 2);  // the sign-of-life trips in a step that repeats
  }
  EXPECT_GT(sol_faults, 10) << static_cast<int>(tg);
}

TEST(E1Shortcuts, Telegram3SameAsWithoutShortcuts) { run_pair(TelegramType::Standard3, 3); }
TEST(E1Shortcuts, Telegram9SameAsWithoutShortcuts) { run_pair(TelegramType::Standard9, 9); }
TEST(E1Shortcuts, Telegram111SameAsWithoutShortcuts) { run_pair(TelegramType::Hiwin111, 111); }

}  // namespace
}  // namespace plc::sim

namespace plc::sim {
namespace {

// The rest repeat's compare of the PLC's bytes (all but STW2, bytes 6 and
// 7 of telegram 111, Table 3.4.1 of the spec): one bit changed in any other
// byte while the drive repeats at rest must take the full step, which finds
// other words and so does not arm the repeat again; a change of STW2 alone
// (the sign-of-life) keeps repeating. Fails when the compare leaves out a
// byte (e.g. the first word's difference shifted by 24, dropping byte 5).
TEST(E1Shortcuts, RestRepeatSeesEveryByteButStw2) {
  using namespace plc::drive;
  using namespace std::chrono_literals;
  int checked = 0;
  for (std::size_t byte = 0; byte < Telegram111Out::kBytes; ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      HiwinE1Config c;
      c.telegram = TelegramType::Hiwin111;
      HiwinE1Model m(c);
      std::vector<std::uint8_t> out(m.output_size()), in(m.input_size());
      TIME now{};
      std::uint8_t sol = 0;
      auto step = [&] {
        sol = next_sign_of_life(sol);
        io::store_be<std::uint16_t>(out, Telegram111Out::kStw2,
                                    static_cast<std::uint16_t>(sol << 12));
        now += 1ms;
        m.step(now, 1ms, out, in);
      };
      io::store_be<std::uint16_t>(out, Telegram111Out::kStw1, 0x043E);
      for (int i = 0; i < 20; ++i) step();
      io::store_be<std::uint16_t>(out, Telegram111Out::kStw1, 0x043F);
      for (int i = 0; i < 2000 && !m.rest_repeating(); ++i) step();
      ASSERT_TRUE(m.rest_repeating()) << "byte " << byte;
      step();  // a repeat: only the sign-of-life changed
      ASSERT_TRUE(m.rest_repeating());
      out[byte] = static_cast<std::uint8_t>(out[byte] ^ (1U << bit));
      step();
      if (byte == Telegram111Out::kStw2 || byte == Telegram111Out::kStw2 + 1) {
        EXPECT_TRUE(m.rest_repeating() || m.state() != HiwinE1Model::State::S4)
            << "byte " << byte << " bit " << bit;
      } else {
        EXPECT_FALSE(m.rest_repeating()) << "byte " << byte << " bit " << bit;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 22 * 8);
}

}  // namespace
}  // namespace plc::sim
