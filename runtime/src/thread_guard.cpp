#include "plc/thread_guard.hpp"

#include <errno.h>  // program_invocation_short_name (GNU)

#include <atomic>
#include <cstdio>

namespace plc {
namespace {
std::atomic<std::uint64_t> g_failures{0};
}

void report_thread_failure(std::string_view thread, std::string_view what) noexcept {
  g_failures.fetch_add(1, std::memory_order_relaxed);
  std::fprintf(stderr, "%s: %.*s: %.*s\n", program_invocation_short_name,
               static_cast<int>(thread.size()), thread.data(), static_cast<int>(what.size()),
               what.data());
  std::fflush(stderr);
}

std::uint64_t thread_failures() noexcept { return g_failures.load(std::memory_order_relaxed); }

}  // namespace plc
