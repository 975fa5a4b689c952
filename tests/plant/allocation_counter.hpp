// Counts heap allocations in this test executable: allocation_counter.cpp
// interposes malloc, calloc and realloc (glibc's own allocator does the
// work), which catches operator new and Eigen's matrices alike (Eigen
// allocates with malloc, not new). A test asserts that a stretch of code
// allocates nothing, e.g. the plant steps of a scan.
//
// Under AddressSanitizer or ThreadSanitizer the sanitizer owns malloc, so
// nothing is interposed and counting() is false: those tests skip there
// (the release build runs them).
#pragma once

#include <cstddef>

namespace plant_test {

[[nodiscard]] bool counting();
// Allocations since the executable started.
[[nodiscard]] std::size_t allocations();

}  // namespace plant_test
