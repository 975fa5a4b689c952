// The entry of every thread the runtime, the plugins, the writers and the
// HMI bridge start: an exception that escapes a thread's function calls
// std::terminate, which ends plcrun without safe outputs, summary or saved
// files. Instead the thread's entry catches it, says so on stderr
// ("plcrun: <thread>: <what>"), counts it (thread_failures(): plcrun's exit
// code is then 1), and hands it to its owner, who puts what the thread
// served into a safe state (a plugin's devices to Fault, a writer's file
// reported FAILED, the cell stopped when its watchdog is gone).
#pragma once

#include <cstdint>
#include <exception>
#include <string_view>

namespace plc {

// Logs "<program>: <thread>: <what>" on stderr and counts it. Never throws.
void report_thread_failure(std::string_view thread, std::string_view what) noexcept;
// Threads of this process that ended by an exception so far.
[[nodiscard]] std::uint64_t thread_failures() noexcept;

// Runs body(); an exception that escapes it is reported (above) and its
// text handed to on_failure(std::string_view), on the same thread. True
// when body() returned normally.
template <class Body, class OnFailure>
bool run_guarded(std::string_view thread, Body&& body, OnFailure&& on_failure) noexcept {
  try {
    body();
    return true;
  } catch (const std::exception& e) {
    report_thread_failure(thread, e.what());
    on_failure(std::string_view(e.what()));
  } catch (...) {
    constexpr std::string_view what = "an exception that is not a std::exception";
    report_thread_failure(thread, what);
    on_failure(what);
  }
  return false;
}

}  // namespace plc
