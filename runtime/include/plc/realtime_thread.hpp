// What a real-time thread asks of the OS: the monotonic clock, absolute
// sleeps on it, and SCHED_FIFO where permitted. The runtime's task threads,
// the fieldbus plugins' cyclic threads and the device simulators' threads
// share these, so that each sleeps and reports a refused priority the same
// way.
#pragma once

#include <cstdint>

namespace plc {

// CLOCK_MONOTONIC in nanoseconds.
std::int64_t mono_ns() noexcept;

// Sleeps until CLOCK_MONOTONIC reaches t (nanoseconds): an absolute
// deadline, so a late wake-up does not shift the releases after it.
// Resumes after a signal.
void sleep_until_ns(std::int64_t t) noexcept;

// Puts the calling thread under SCHED_FIFO at `priority` (1..99). 0 when
// done, else pthread_setschedparam's error: EPERM without root or
// CAP_SYS_NICE, where the thread goes on at its normal priority.
int set_fifo_priority(int priority) noexcept;

// The warning for a refused SCHED_FIFO, on stderr:
// "<who>: warning: SCHED_FIFO not permitted (<error>); <consequence>".
// `who` names the program or plugin that asked, `consequence` what now runs
// at normal priority.
void warn_fifo_refused(const char* who, int error, const char* consequence) noexcept;

}  // namespace plc
