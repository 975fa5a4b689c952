#include "allocation_counter.hpp"

#include <atomic>

#include "plc_test_sanitizers.hpp"

namespace {
std::atomic<std::size_t> g_allocations{0};
}

namespace plant_test {
std::size_t allocations() { return g_allocations.load(); }
bool counting() { return !plctest::kSanitized; }
}  // namespace plant_test

#if !PLC_TEST_ASAN && !PLC_TEST_TSAN
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);

void* malloc(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t s) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, s);
}
void* realloc(void* p, std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
}
#endif
