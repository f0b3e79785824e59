#pragma once
// Whether this test binary runs under AddressSanitizer (./tests/sanitize.sh builds with clang,
// which has __has_feature; gcc defines __SANITIZE_ADDRESS__), and how much slower its processes
// are then: tests that wait on real processes scale their deadlines by it (the ctest timeouts
// of a sanitizer build are scaled by the same factor, cmake/SricsHelpers.cmake).

#if defined(__SANITIZE_ADDRESS__)
#define SRICS_TESTING_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SRICS_TESTING_ASAN 1
#endif
#endif

namespace srics::testing {
#ifdef SRICS_TESTING_ASAN
inline constexpr int kSanitizerSlowdown = 4;
#else
inline constexpr int kSanitizerSlowdown = 1;
#endif
}  // namespace srics::testing
