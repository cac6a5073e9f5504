// Tests of the Compact RINEX (Hatanaka) decoder against RNX2CRX 4.1.0 pairs in
// ../shared/data/hatanaka (README.md there: each .crx restores to the .rnx beside
// it), plus synthetic corrupt inputs.
#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/hatanaka_decoder.h"
#include "ppp_bayes_tree/io/rinex_obs_reader.h"
#include "test_support.h"

namespace ppp {
namespace {

std::vector<std::string> allLines(LineSource& src) {
  std::vector<std::string> lines;
  std::string line;
  while (src.next(line)) lines.push_back(line);
  return lines;
}

std::string rstrip(std::string s) {
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

/// Decodes `crx` and compares every line with `rnx`. CRX2RNX writes no trailing
/// blanks; the reference files have none either, but we compare right-stripped
/// reference lines so that the test states that convention explicitly.
void expectSameLines(std::unique_ptr<LineSource> decoded, const std::string& rnx_path) {
  auto reference = openLineSource(rnx_path);
  const auto want = allLines(*reference);
  const auto got = allLines(*decoded);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    ASSERT_EQ(got[i], rstrip(want[i])) << "line " << i + 1;
  }
}

TEST(Hatanaka, Crinex3MatchesRinex305LineForLine) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string base = test::dataPath("hatanaka/ESBC00DNK_R_20201770000_01D_30S_MO_trim");
  auto src = openObservationSource(base + ".crx");
  auto* crx = dynamic_cast<HatanakaDecoder*>(src.get());
  ASSERT_NE(crx, nullptr);
  EXPECT_EQ(crx->crinexVersion(), 3);
  expectSameLines(std::move(src), base + ".rnx");
}

TEST(Hatanaka, Crinex1MatchesRinex211LineForLine) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string base = test::dataPath("hatanaka/algo0010_2015001_v1_trim");
  auto src = openObservationSource(base + ".crx");
  auto* crx = dynamic_cast<HatanakaDecoder*>(src.get());
  ASSERT_NE(crx, nullptr);
  EXPECT_EQ(crx->crinexVersion(), 1);
  expectSameLines(std::move(src), base + ".rnx");
}

TEST(Hatanaka, PlainRinexPassesThroughUnwrapped) {
  PPP_REQUIRE_SHARED_DATA();
  auto src = openObservationSource(test::dataPath("hatanaka/algo0010_2015001_v1_trim.rnx"));
  EXPECT_EQ(dynamic_cast<HatanakaDecoder*>(src.get()), nullptr);
}

TEST(Hatanaka, GzipCompressedCrxDecodesTheSame) {
  PPP_REQUIRE_SHARED_DATA();
  for (const std::string stem : {"ESBC00DNK_R_20201770000_01D_30S_MO_trim", "algo0010_2015001_v1_trim"}) {
    const std::string base = test::dataPath("hatanaka/" + stem);
    const std::string bytes = test::readFileBytes(base + ".crx");
    const auto dir = test::tempDir("crxgz");
    const std::string gz = (dir / (stem + ".crx.gz")).string();
    gzFile f = gzopen(gz.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, bytes.data(), static_cast<unsigned>(bytes.size())), static_cast<int>(bytes.size()));
    gzclose(f);
    auto src = openObservationSource(gz);
    ASSERT_NE(dynamic_cast<HatanakaDecoder*>(src.get()), nullptr);
    EXPECT_TRUE(src->compressed());
    expectSameLines(std::move(src), base + ".rnx");
    std::filesystem::remove_all(dir);
  }
}

TEST(Hatanaka, ReaderReadsCrxLikeRnx) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string base = test::dataPath("hatanaka/ESBC00DNK_R_20201770000_01D_30S_MO_trim");
  RinexObsReader a = RinexObsReader::open(base + ".crx");
  RinexObsReader b = RinexObsReader::open(base + ".rnx");
  EXPECT_TRUE(a.compactRinex());
  EXPECT_FALSE(b.compactRinex());
  ObsEpoch ea, eb;
  int n = 0;
  while (a.next(ea)) {
    ASSERT_TRUE(b.next(eb));
    ASSERT_EQ(ea.time, eb.time);
    ASSERT_EQ(ea.observations.size(), eb.observations.size());
    for (std::size_t i = 0; i < ea.observations.size(); ++i) {
      EXPECT_EQ(ea.observations[i].value, eb.observations[i].value);
      EXPECT_EQ(ea.observations[i].lli, eb.observations[i].lli);
      EXPECT_EQ(ea.observations[i].ssi, eb.observations[i].ssi);
    }
    ++n;
  }
  EXPECT_FALSE(b.next(eb));
  EXPECT_EQ(n, 2);  // README.md: "2 epochs"
  EXPECT_TRUE(a.report().clean()) << a.report().summary();
}

}  // namespace
}  // namespace ppp
