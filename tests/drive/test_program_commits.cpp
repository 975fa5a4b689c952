// DriveAxis::set_program_commits (issue 23): a program with several blocks
// on one axis writes the PLC's telegram once per scan, after the last
// block, and the drive gets the same bytes in every scan as when every
// block writes it (spec §3.2 telegram 111 words, §7.6 task handshake,
// §10.2 fault acknowledge edges).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "drive_test_util.hpp"
#include "plc/fb/drive/mc_blocks.hpp"

namespace plc::drive::test {
namespace {

// The filling cell's blocks on its conveyor, in its order: power, index,
// reset; with program_commits the cell's single commit() after them.
struct Cell {
  explicit Cell(bool program_commits) : commits(program_commits) {
    b.axis.set_program_commits(program_commits);
  }
  void body() {
    power(b.ctx, b.axis);
    index(b.ctx, b.axis);
    reset(b.ctx, b.axis);
    if (commits) b.axis.commit();
  }
  std::vector<std::uint8_t> wire() const {
    const auto o = b.dev->outputs();
    return {o.begin(), o.end()};
  }
  bool commits;
  Bench b;
  MC_Power power;
  MC_MoveRelative index;
  MC_Reset reset;
};

TEST(ProgramCommits, SameTelegramOnTheWireInEveryScanAsCommitsAfterEveryBlock) {
  Cell every(false), once(true);
  int scan = 0;
  int moves_before = 0, moves_after = 0, resets_done = 0, reset_errors = 0;
  // Both cells get the same inputs from the same script; their drives must
  // see the same telegram in every scan.
  auto step = [&](auto&& script) {
    for (Cell* c : {&every, &once}) script(*c);
    for (Cell* c : {&every, &once}) c->b.scan([&] { c->body(); });
    ++scan;
    ASSERT_EQ(every.wire(), once.wire()) << "scan " << scan;
    ASSERT_EQ(every.b.axis.State, once.b.axis.State) << "scan " << scan;
  };
  for (int i = 0; i < 3000 && !HasFatalFailure(); ++i) {
    step([&](Cell& c) {
      c.power.Enable = !c.reset.Busy && c.b.axis.State != AxisState::ErrorStop;
      // Back-to-back moves: Execute drops for one scan after each Done.
      c.index.Distance = 20000;
      c.index.Velocity = 400000;
      c.index.Execute = !c.index.Done && !c.index.Error;
      // MC_Reset while in ErrorStop, a new Execute edge after a timeout.
      c.reset.Execute = c.b.axis.State == AxisState::ErrorStop && !c.reset.Done && !c.reset.Error;
      // A drive fault in the middle of a move whose cause stays for 50
      // scans: the first reset times out (its cause is still there), the
      // second one clears it.
      if (i == 700) c.b.model->trip_alarm(0x710, true);
      if (i == 750) c.b.model->clear_alarm_cause();
    });
    if (once.index.Done) ++(i < 700 ? moves_before : moves_after);
    if (once.reset.Done) ++resets_done;
    if (once.reset.Error) ++reset_errors;
  }
  // The script went through what it is there for: moves before and after
  // the fault, and the reset of the fault.
  EXPECT_GT(moves_before, 3);
  EXPECT_GT(moves_after, 3);
  EXPECT_GT(reset_errors, 0);
  EXPECT_GT(resets_done, 0);
  EXPECT_EQ(every.b.ack_edges, once.b.ack_edges);
  EXPECT_GT(once.b.ack_edges, 0);
}

TEST(ProgramCommits, BlocksLeaveTheTelegramToTheProgram) {
  Cell c(true);
  c.power.Enable = true;
  c.b.scan([&] { c.body(); });
  const std::vector<std::uint8_t> sent = c.wire();
  // A scan in which the program calls its blocks but does not commit: the
  // outputs stay as the last commit left them (the controller sign-of-life
  // in STW2 does not move).
  c.power(c.b.ctx, c.b.axis);
  c.index(c.b.ctx, c.b.axis);
  c.reset(c.b.ctx, c.b.axis);
  const auto out = c.b.axis.Port.out();
  EXPECT_TRUE(std::equal(out.begin(), out.end(), sent.begin(), sent.end()));
  c.b.axis.commit();
  EXPECT_FALSE(std::equal(out.begin(), out.end(), sent.begin(), sent.end()));
}

}  // namespace
}  // namespace plc::drive::test
