// The batch tools' allocator setting (app/allocator_tuning.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <vector>

#include "ppp_bayes_tree/app/allocator_tuning.h"

// Under AddressSanitizer (scripts/test_sanitizers.sh) the sanitizer's allocator serves
// malloc and its mallopt applies nothing (it returns 0).
#if defined(__SANITIZE_ADDRESS__)
#define PPP_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PPP_TEST_UNDER_ASAN 1
#endif
#endif

TEST(AllocatorTuning, FastBinsOffWithTheGnuCLibraryAndMemoryStillServed) {
#if defined(PPP_TEST_UNDER_ASAN)
  EXPECT_FALSE(ppp::useAllocatorWithoutFastBins());
#elif defined(__GLIBC__)
  EXPECT_TRUE(ppp::useAllocatorWithoutFastBins());
#else
  EXPECT_FALSE(ppp::useAllocatorWithoutFastBins());
#endif
  // Small frees followed by a large request (the pattern the setting is for).
  std::vector<std::unique_ptr<int[]>> small;
  for (int i = 0; i < 1000; ++i) small.emplace_back(new int[4]{i, i, i, i});
  for (std::size_t i = 0; i < small.size(); i += 2) small[i].reset();
  std::vector<double> large(100000, 1.5);
  EXPECT_EQ(large.back(), 1.5);
  EXPECT_EQ(small[1][3], 1);
}
