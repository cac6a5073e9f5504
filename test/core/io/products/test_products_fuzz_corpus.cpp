// Runs the SP3 and RINEX clock fuzz entries over their seed corpora and over
// every malformed fixture, so the entries build with the normal tests and the
// seeds are known not to throw anything undocumented.
#include <gtest/gtest.h>

#include <filesystem>

#include "fuzz/rinex_clock_fuzz_entry.h"
#include "fuzz/sp3_fuzz_entry.h"
#include "test_support.h"

namespace ppp {
namespace {

template <class Entry>
std::size_t runDirectory(const std::string& dir, Entry entry) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string bytes = test::readFileBytes(e.path().string());
    EXPECT_NO_THROW(entry(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) << e.path();
    ++n;
  }
  return n;
}

TEST(ProductsFuzzCorpus, Sp3SeedsAndFixtures) {
  EXPECT_GE(runDirectory(std::string(PPP_FUZZ_DIR) + "/corpus/sp3", fuzz::fuzzSp3), 4u);
  EXPECT_GE(runDirectory(test::fixturePath("malformed/sp3"), fuzz::fuzzSp3), 8u);
}

TEST(ProductsFuzzCorpus, RinexClockSeedsAndFixtures) {
  EXPECT_GE(runDirectory(std::string(PPP_FUZZ_DIR) + "/corpus/rinex_clock", fuzz::fuzzRinexClock), 4u);
  EXPECT_GE(runDirectory(test::fixturePath("malformed/rinex_clock"), fuzz::fuzzRinexClock), 7u);
}

}  // namespace
}  // namespace ppp
