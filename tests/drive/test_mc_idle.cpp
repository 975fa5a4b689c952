// McExecute::idle_call (issue 23): MC_Reset, MC_MoveAbsolute and
// MC_MoveRelative handle an idle call (Execute FALSE, not Busy) inline and
// make the library call (run()) only otherwise. A cell whose blocks are
// called through operator() must show, scan by scan, the same block
// outputs, axis state and telegram on the wire as one whose blocks always
// make the whole call, over moves, refusals (Error with ErrorID), a drive
// fault with a reset that times out and one that clears it, and Execute
// pulses of every length.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "drive_test_util.hpp"
#include "plc/fb/drive/mc_blocks.hpp"

namespace plc::drive::test {
namespace {

struct Cell {
  explicit Cell(bool whole, bool program_commits) : whole_call(whole), commits(program_commits) {
    b.axis.set_program_commits(program_commits);
  }
  template <class Fb>
  void call(Fb& fb) {
    if (whole_call)
      fb.run(b.ctx, b.axis);
    else
      fb(b.ctx, b.axis);
  }
  void body() {
    power(b.ctx, b.axis);
    call(index);
    call(absolute);
    call(reset);
    if (commits) b.axis.commit();
  }
  std::vector<std::uint8_t> wire() const {
    const auto o = b.dev->outputs();
    return {o.begin(), o.end()};
  }
  bool whole_call;
  bool commits;
  Bench b;
  MC_Power power;
  MC_MoveRelative index;
  MC_MoveAbsolute absolute;
  MC_Reset reset;
};

::testing::AssertionResult same_outputs(const McExecute& a, const McExecute& b, const char* name) {
  if (a.Execute == b.Execute && a.Done == b.Done && a.Busy == b.Busy && a.Active == b.Active &&
      a.CommandAborted == b.CommandAborted && a.Error == b.Error && a.ErrorID == b.ErrorID)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << name << ": Done " << a.Done << "/" << b.Done << " Busy " << a.Busy << "/" << b.Busy
         << " Active " << a.Active << "/" << b.Active << " Aborted " << a.CommandAborted << "/"
         << b.CommandAborted << " Error " << a.Error << "/" << b.Error << " ErrorID " << a.ErrorID
         << "/" << b.ErrorID;
}

void run_pair(bool program_commits, unsigned seed) {
  Cell inline_idle(false, program_commits), whole(true, program_commits);
  std::mt19937 rng(seed);
  int idle_calls = 0, errors_cleared = 0, moves_done = 0, resets_done = 0;
  for (int i = 0; i < 6000; ++i) {
    // One draw per scan for both cells: the same script.
    const std::uint32_t r = rng();
    for (Cell* c : {&inline_idle, &whole}) {
      Cell& k = *c;
      // Power off now and then (moves refused: Error kErrDisabled).
      k.power.Enable =
          !k.reset.Busy && k.b.axis.State != AxisState::ErrorStop && (i / 400) % 5 != 3;
      k.index.Distance = (r & 1) ? 20000 : -15000;
      k.index.Velocity = 400000;
      // Execute held until Done/Error, then dropped for a random number of
      // scans; sometimes dropped while Busy (the output shows a scan).
      if (k.index.Done || k.index.Error)
        k.index.Execute = (r % 7) == 0;
      else if (!k.index.Execute)
        k.index.Execute = (r % 5) == 0;
      else if ((r % 97) == 0)
        k.index.Execute = false;
      k.absolute.Position = (r & 2) ? 0 : 120000;
      k.absolute.Velocity = (r % 11) == 0 ? -1 : 300000;  // refused now and then
      k.absolute.Execute = (i % 900) > 850 && !k.absolute.Done && !k.absolute.Error;
      // MC_Reset while in ErrorStop; drops Execute once it ended.
      k.reset.Execute =
          k.b.axis.State == AxisState::ErrorStop && !k.reset.Done && !k.reset.Error && (r % 3) != 0;
      // Drive faults whose cause stays 50 scans: a reset in between times
      // out, one after clears it.
      if (i % 1500 == 700) k.b.model->trip_alarm(0x710, true);
      if (i % 1500 == 750) k.b.model->clear_alarm_cause();
    }
    const bool idle_before = !inline_idle.index.Execute && !inline_idle.index.Busy;
    const bool errored_before = inline_idle.index.Error || inline_idle.reset.Error;
    for (Cell* c : {&inline_idle, &whole}) c->b.scan([&] { c->body(); });
    if (idle_before) ++idle_calls;
    if (errored_before && !inline_idle.index.Error && !inline_idle.reset.Error) ++errors_cleared;
    if (inline_idle.index.Done) ++moves_done;
    if (inline_idle.reset.Done) ++resets_done;
    ASSERT_EQ(inline_idle.wire(), whole.wire()) << "scan " << i;
    ASSERT_EQ(inline_idle.b.axis.State, whole.b.axis.State) << "scan " << i;
    ASSERT_TRUE(same_outputs(inline_idle.index, whole.index, "MC_MoveRelative")) << "scan " << i;
    ASSERT_TRUE(same_outputs(inline_idle.absolute, whole.absolute, "MC_MoveAbsolute"))
        << "scan " << i;
    ASSERT_TRUE(same_outputs(inline_idle.reset, whole.reset, "MC_Reset")) << "scan " << i;
  }
  // The script went through what it is there for.
  EXPECT_GT(idle_calls, 500);
  EXPECT_GT(errors_cleared, 3);
  EXPECT_GT(moves_done, 10);
  EXPECT_GT(resets_done, 1);
  EXPECT_EQ(inline_idle.b.ack_edges, whole.b.ack_edges);
}

TEST(McIdleCall, SameAsTheWholeCallWithCommitsAfterEveryBlock) { run_pair(false, 1); }
TEST(McIdleCall, SameAsTheWholeCallWithProgramCommits) { run_pair(true, 2); }

}  // namespace
}  // namespace plc::drive::test
