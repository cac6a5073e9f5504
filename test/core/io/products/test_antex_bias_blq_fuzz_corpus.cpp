// Runs the fuzz entries of the ANTEX, Bias-SINEX and BLQ readers over their
// seed corpora and over every truncation of each seed, so that the entries stay
// compiled and the "never crash on broken input" rule is checked in every build
// (the sanitizer runs themselves use libFuzzer, see test/fuzz).
#include <gtest/gtest.h>

#include <filesystem>

#include "fuzz/antex_fuzz_entry.h"
#include "fuzz/bias_sinex_fuzz_entry.h"
#include "fuzz/blq_fuzz_entry.h"
#include "test_support.h"

namespace {

template <typename Entry>
std::size_t runCorpus(const std::string& name, Entry entry) {
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(PPP_FUZZ_DIR) + "/corpus/" + name)) {
    const std::string bytes = ppp::test::readFileBytes(e.path().string());
    const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
    for (std::size_t cut = 0; cut <= bytes.size(); cut += 37) entry(data, cut);
    entry(data, bytes.size());
    ++files;
  }
  return files;
}

}  // namespace

TEST(FuzzCorpus, AntexSeedsAndTruncationsDoNotCrash) {
  EXPECT_GE(runCorpus("antex", ppp::fuzz::fuzzAntex), 3u);
}

TEST(FuzzCorpus, BiasSinexSeedsAndTruncationsDoNotCrash) {
  EXPECT_GE(runCorpus("bias_sinex", ppp::fuzz::fuzzBiasSinex), 3u);
}

TEST(FuzzCorpus, BlqSeedsAndTruncationsDoNotCrash) {
  EXPECT_GE(runCorpus("blq", ppp::fuzz::fuzzBlq), 2u);
}
