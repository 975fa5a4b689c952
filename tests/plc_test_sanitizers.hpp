// Which sanitizer this test build has, for the few tests whose assertions
// or mechanisms differ under one (GCC defines __SANITIZE_*, clang answers
// __has_feature). PLC_TEST_ASAN / PLC_TEST_TSAN are 1 or 0 for #if; the
// constants below are the same for ordinary code.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define PLC_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PLC_TEST_ASAN 1
#endif
#endif
#ifndef PLC_TEST_ASAN
#define PLC_TEST_ASAN 0
#endif

#if defined(__SANITIZE_THREAD__)
#define PLC_TEST_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PLC_TEST_TSAN 1
#endif
#endif
#ifndef PLC_TEST_TSAN
#define PLC_TEST_TSAN 0
#endif

namespace plctest {
inline constexpr bool kThreadSanitizer = PLC_TEST_TSAN == 1;
inline constexpr bool kSanitized = PLC_TEST_ASAN == 1 || PLC_TEST_TSAN == 1;  // ASan or TSan
}  // namespace plctest
