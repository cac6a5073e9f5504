// Tests of the Compact RINEX (Hatanaka) decoder against RNX2CRX 4.1.0 pairs in
// ../shared/data/hatanaka (README.md there: each .crx restores to the .rnx beside
// it), plus synthetic corrupt inputs.
#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "fuzz/hatanaka_fuzz_entry.h"
#include "fuzz/rinex_obs_fuzz_entry.h"
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
/// blanks and neither the decoder nor the two reference .rnx files have any
/// (checked below), so the comparison is exact.
void expectSameLines(std::unique_ptr<LineSource> decoded, const std::string& rnx_path) {
  auto reference = openLineSource(rnx_path);
  const auto want = allLines(*reference);
  const auto got = allLines(*decoded);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    ASSERT_EQ(want[i], rstrip(want[i])) << "reference line " << i + 1 << " has trailing blanks";
    ASSERT_EQ(got[i], want[i]) << "line " << i + 1;
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


// ------------------------------------------------------------- synthetic CRX

std::string hdr(const std::string& content, const std::string& label) {
  std::string s = content;
  s.resize(60, ' ');
  return s + label + "\n";
}

const std::string kCrx3Header =
    hdr("3.0                 COMPACT RINEX FORMAT", "CRINEX VERS   / TYPE") +
    hdr("RNX2CRX ver.4.1.0                       04-Jun-26 21:21", "CRINEX PROG / DATE") +
    hdr("     3.05           OBSERVATION DATA    M", "RINEX VERSION / TYPE") +
    hdr("G    2 C1C L1C", "SYS / # / OBS TYPES") + hdr("", "END OF HEADER");

std::vector<std::string> decodeAll(const std::string& text, std::vector<ParseProblem>* problems = nullptr) {
  auto src = observationSource(memoryLineSource(text, "synthetic.crx"));
  auto* crx = dynamic_cast<HatanakaDecoder*>(src.get());
  EXPECT_NE(crx, nullptr);
  auto lines = allLines(*src);
  if (problems != nullptr && crx != nullptr) *problems = crx->takeProblems();
  return lines;
}

TEST(HatanakaSynthetic, Crinex3ClockFlagsEventsEscapesAndRecovery) {
  const std::string body =
      "> 2021 01 01 00 00 00.0000000  0  2      G01G02\n"
      "2&123456789\n"
      "3&20000000123 3&100000000456   18\n"
      "3&21000000000\n"
      + std::string(19, ' ') + "3\n"          // epoch line difference: seconds 00 -> 30
      "1000\n"                                  // clock: first difference
      "1000 2000\n"                             // G01: first differences, flags kept
      "500\n"                                   // G02: L1C stays blank
      "& an escape line of CRINEX 3\n"
      "> 2021 01 01 00 00 45.0000000  4  1\n"   // event: one header line follows
      + hdr("EVENT COMMENT", "COMMENT") +
      "> 2021 01 01 00 01 00.0000000  0  1      G01\n"
      "\n"                                      // no clock
      "3&20000005000 3&100000005000\n"
      + std::string(19, ' ') + "3\n"
      "\n"
      "x12 1\n"                                 // corrupt field: epoch dropped
      + std::string(19, ' ') + "4\n"            // not initialised: skipped
      "\n"
      "1 1\n"
      "> 2021 01 01 00 02 00.0000000  0  1      G01\n"
      "\n"
      "1&7000 1&-500\n";
  std::vector<ParseProblem> problems;
  const auto lines = decodeAll(kCrx3Header + body, &problems);
  const std::vector<std::string> want = {
      "     3.05           OBSERVATION DATA    M                   RINEX VERSION / TYPE",
      "G    2 C1C L1C                                              SYS / # / OBS TYPES",
      "                                                            END OF HEADER",
      "> 2021 01 01 00 00 00.0000000  0  2        .000123456789",
      "G01  20000000.123   100000000.45618",
      "G02  21000000.000",
      "> 2021 01 01 00 00 30.0000000  0  2        .000123457789",
      "G01  20000001.123   100000002.45618",
      "G02  21000000.500",
      "> 2021 01 01 00 00 45.0000000  4  1",
      "EVENT COMMENT                                               COMMENT",
      "> 2021 01 01 00 01 00.0000000  0  1",
      "G01  20000005.000   100000005.000",
      "> 2021 01 01 00 02 00.0000000  0  1",
      "G01         7.000           -.500",
  };
  EXPECT_EQ(lines, want);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].line, 22u);  // the "x12 1" line of the .crx text
  EXPECT_NE(problems[0].reason.find("bad data field 'x12'"), std::string::npos) << problems[0].reason;
}

TEST(HatanakaSynthetic, Crinex1ClockContinuationAndBlankFlags) {
  std::string text = hdr("1.0                 COMPACT RINEX FORMAT", "CRINEX VERS   / TYPE") +
                     hdr("RNX2CRX ver.4.1.0                       04-Jun-26 21:21", "CRINEX PROG / DATE") +
                     hdr("     2.11           OBSERVATION DATA    G (GPS)", "RINEX VERSION / TYPE") +
                     hdr("     2    C1    L1", "# / TYPES OF OBSERV") + hdr("", "END OF HEADER");
  text += "&21  1  1  0  0  0.0000000  0 13G01G02G03G04G05G06G07G08G09G10G11G12G13\n";
  text += "1&-1500000000\n";
  for (int i = 0; i < 12; ++i) text += "3&20000000000 3&100000000000\n";
  text += " 3&100000000000  &1\n";  // G13: blank C1 with a flag (CRINEX 1 blanks it), L1 LLI 1
  const auto lines = decodeAll(text);
  ASSERT_EQ(lines.size(), 3u + 2u + 13u);
  EXPECT_EQ(lines[3], " 21  1  1  0  0  0.0000000  0 13G01G02G03G04G05G06G07G08G09G10G11G12-1.500000000");
  EXPECT_EQ(lines[4], std::string(32, ' ') + "G13");
  EXPECT_EQ(lines[5], "  20000000.000   100000000.000");
  EXPECT_EQ(lines[17], std::string(16, ' ') + " 100000000.0001");
  // And the reader makes sense of it.
  RinexObsReader reader(observationSource(memoryLineSource(text, "x.crx")));
  ObsEpoch e;
  ASSERT_TRUE(reader.next(e));
  EXPECT_DOUBLE_EQ(*e.receiver_clock_offset_s, -1.5);
  ASSERT_EQ(e.satellites.size(), 13u);
  const Observation* l1 = e.find(*SatelliteId::parse("G13"), *ObservationCode::parse("L1C"));
  EXPECT_DOUBLE_EQ(*l1->value, 100000000.0);
  EXPECT_EQ(l1->lli, 1);
  EXPECT_FALSE(e.find(*SatelliteId::parse("G13"), *ObservationCode::parse("C1C"))->value);
}

TEST(HatanakaSynthetic, HostileInputIsRejectedNotAllocated) {
  const std::string init = "> 2021 01 01 00 00 00.0000000  0  1      G01\n\n";
  struct Case {
    std::string body;
    const char* reason;
  };
  const Case cases[] = {
      {init + "3&1234567890123456789 1\n", "bad data field"},            // 19 digits
      // 18 digits parse, but the value cannot be written as F14.3. (With every
      // written value in range, the higher differences stay far from 2^63; the
      // decoder still checks each sum for overflow.)
      {init + "9&900000000000000000 9&1\n", "out of the F14.3 range"},
      {init + "3&99999999999999 3&1\n", "out of the F14.3 range"},
      {init + "3&1 1\n", "difference without arc initialisation for G01"},
      {"> 2021 01 01 00 00 00.0000000  0999      G01\n\n", "bad satellite count or list"},
      {"> 2021 01 01 00 00 00.0000000  0  1      R01\n\n1\n", "without observation types"},
      {init + "12&5 1\n", "bad data field"},
      {"> 2021 01 01 00 00 00.0000000  0  1      G01\n1\n", "receiver clock difference without"},
      {"> garbage\n", "bad epoch line"},
  };
  for (const auto& c : cases) {
    std::vector<ParseProblem> problems;
    const auto lines = decodeAll(kCrx3Header + c.body, &problems);
    EXPECT_EQ(lines.size(), 3u) << c.body;  // the header only
    ASSERT_EQ(problems.size(), 1u) << c.body;
    EXPECT_NE(problems[0].reason.find(c.reason), std::string::npos) << problems[0].reason;
  }
}

TEST(HatanakaSynthetic, TruncatedEpochIsDroppedAndReported) {
  std::vector<ParseProblem> problems;
  const auto lines = decodeAll(kCrx3Header + "> 2021 01 01 00 00 00.0000000  0  2      G01G02\n\n3&1 3&2\n",
                               &problems);
  EXPECT_EQ(lines.size(), 3u);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].reason.find("truncated"), std::string::npos);
}

TEST(HatanakaSynthetic, BadCrinexHeaderThrowsParseError) {
  const std::string v2 = hdr("2.0                 COMPACT RINEX FORMAT", "CRINEX VERS   / TYPE") +
                         hdr("RNX2CRX", "CRINEX PROG / DATE");
  try {
    observationSource(memoryLineSource(v2, "bad.crx"));
    ADD_FAILURE() << "no ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 1u);
    EXPECT_NE(e.reason().find("unsupported Compact RINEX version '2.0'"), std::string::npos);
  }
  const std::string no_prog = hdr("3.0                 COMPACT RINEX FORMAT", "CRINEX VERS   / TYPE") +
                              hdr("     3.05           OBSERVATION DATA    M", "RINEX VERSION / TYPE");
  try {
    observationSource(memoryLineSource(no_prog, "bad.crx"));
    ADD_FAILURE() << "no ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2u);
    EXPECT_NE(e.reason().find("CRINEX PROG / DATE"), std::string::npos);
  }
}

// The fuzz entries run over their seed corpora (and every fixture) without
// throwing anything else than the documented exceptions, which they catch.
TEST(HatanakaFuzzEntries, SeedCorporaRun) {
  std::size_t files = 0;
  for (const char* dir : {"/corpus/hatanaka", "/corpus/rinex_obs"}) {
    for (const auto& entry : std::filesystem::directory_iterator(std::string(PPP_FUZZ_DIR) + dir)) {
      const std::string bytes = test::readFileBytes(entry.path().string());
      const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
      EXPECT_NO_THROW(fuzz::fuzzHatanaka(data, bytes.size())) << entry.path();
      EXPECT_NO_THROW(fuzz::fuzzRinexObs(data, bytes.size())) << entry.path();
      ++files;
    }
  }
  EXPECT_GE(files, 10u);
}

}  // namespace
}  // namespace ppp
