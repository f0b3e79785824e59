// The actor fast path makes no heap allocation once warmed up. malloc is interposed for this
// executable only (glibc: forward to __libc_malloc) and counted around the calls; Eigen and
// operator new both allocate through malloc. Under AddressSanitizer (./tests/sanitize.sh), whose
// own malloc an interposed one would bypass, its allocation hook counts instead (it sees every
// malloc, calloc, realloc and operator new).
#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>

#include "common/rl/networks.h"
#include "tests/common/rl/network_configs.h"

#include "tests/sanitizer.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_mallocs{0};
}  // namespace

#ifdef SRICS_TESTING_ASAN
#include <sanitizer/allocator_interface.h>

namespace {
void CountAllocation(const volatile void*, size_t) {
  if (g_counting.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1);
}
void IgnoreFree(const volatile void*) {}
const int g_hooks_installed = __sanitizer_install_malloc_and_free_hooks(CountAllocation, IgnoreFree);
}  // namespace
#else
extern "C" void* __libc_malloc(size_t size);

extern "C" void* __libc_memalign(size_t alignment, size_t size);

extern "C" void* malloc(size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1);
  return __libc_malloc(size);
}

// aligned allocations too: oneDNN allocates its buffers with posix_memalign (the ASan build
// saw 3 per action when small products went to oneDNN; this build's counter did not)
extern "C" int posix_memalign(void** out, size_t alignment, size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1);
  *out = __libc_memalign(alignment, size);
  return *out ? 0 : ENOMEM;
}

extern "C" void* aligned_alloc(size_t alignment, size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1);
  return __libc_memalign(alignment, size);
}
#endif

namespace srics::rl {
namespace {

TEST(PolicyActTest, NoHeapAllocationInSteadyState) {
  const AttentionNetworkConfig c = testing::PaperNetworkConfig(7);
  nn::Rng rng(1);
  PolicyNetwork<float> policy("policy", c, rng);
  const nn::Tensor ents = nn::Tensor::Random(7, 9);
  const nn::Tensor goal = nn::Tensor::Random(1, 10);
  float sink = policy.Act(ents, goal, false, rng)(0, 0);  // warm-up sizes the buffers
  // the counter works
#ifdef SRICS_TESTING_ASAN
  ASSERT_NE(g_hooks_installed, 0);
#endif
  g_counting = true;
  void* p = std::malloc(16);
  asm volatile("" : : "r"(p) : "memory");  // clang at -O1 drops an unused malloc/free pair
  g_counting = false;
  std::free(p);
  ASSERT_EQ(g_mallocs.load(), 1);
  g_mallocs = 0;
  g_counting = true;
  for (int i = 0; i < 100; ++i) {
    sink += policy.Act(ents, goal, i % 2 == 0, rng)(0, 1);
  }
  g_counting = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  // and the counter does see Eigen: a larger entity set grows the buffers once
  const nn::Tensor more = nn::Tensor::Random(12, 9);
  g_counting = true;
  sink += policy.Act(more, goal, true, rng)(0, 0);
  g_counting = false;
  EXPECT_GT(g_mallocs.load(), 0);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace srics::rl
