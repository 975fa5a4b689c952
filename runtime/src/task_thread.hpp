// A real-time task thread that a run leaves behind (issue 10, point 4).
//
// When the watchdog stops a task whose program never returns, run() cannot
// join its thread; it leaves it inside the program. The thread may come
// back from the program at any later time, also after the Runtime is gone.
// So the thread and the Runtime share this record (the thread holds its
// share for its whole life), and the thread's state decides, with one
// compare-and-swap on each side, who may touch what:
//
//   InRuntime  the thread runs runtime code (latch, hooks, merge, sleep);
//   InProgram  the thread is inside a program's cycle(), the only place a
//              scan can stay forever;
//   LeftBehind run() detached it (from InProgram): when the program returns,
//              the thread touches nothing of the Runtime and ends;
//   Exited     it came back while left behind and ended without touching;
//   Abandoned  the Runtime was destroyed while the thread was still in the
//              program: the task (its private image, which the program's
//              located variables point into) and the task's programs moved
//              into this record, so the program runs on in memory it
//              co-owns; they are destroyed with the record, by whichever
//              side lets go of it last.
//
// A thread that is not a real-time task thread has no record (current() is
// nullptr); enter/leave then cost a thread-local load.
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "plc/program.hpp"
#include "plc/runtime.hpp"

namespace plc {

struct TaskThread {
  enum State : int { InRuntime, InProgram, LeftBehind, Exited, Abandoned };
  std::atomic<int> state{InRuntime};
  TaskRuntime* owner = nullptr;  // the task the thread runs (set before it starts)
  // Abandoned: what the program may still touch.
  std::unique_ptr<TaskRuntime> task;
  std::vector<std::unique_ptr<Program>> programs;

  // The record of the calling thread (set by the real-time task thread).
  static TaskThread*& current() {
    thread_local TaskThread* self = nullptr;
    return self;
  }
  static void enter_program() {
    if (TaskThread* s = current()) s->state.store(InProgram);
  }
  // After a program's cycle() (returned or threw): false when the run left
  // this thread behind, which must then return without touching anything.
  static bool leave_program() {
    TaskThread* s = current();
    if (!s) return true;
    int seen = InProgram;
    if (s->state.compare_exchange_strong(seen, InRuntime) || seen == InRuntime) return true;
    if (seen == LeftBehind) s->state.compare_exchange_strong(seen, Exited);
    return false;
  }
};

}  // namespace plc
