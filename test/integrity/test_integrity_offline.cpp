// Integrity regression suite, offline ("never confidently wrong, every
// loss counted, every start-up error said"): the broken and mismatched inputs of
// the issue, replayed through ppp_solve's run (solvePppEstimators, both
// estimators) on copies made here at run time from ../shared/data (never
// committed), each against its target:
//  - one bad SP3 value (ZIM2 G15 X +1 m at line 104; G24 X +1 m at 00:30): EKF,
//    filtered and smoothed mean and max within 2x of the clean run of this test
//    binary; the bad node named among the run's problems;
//  - the same G15 error with the product sanity check OFF: the estimators' own
//    postfit checks (the smoother's included) must keep both within 2x;
//  - a 1 us clock jump (ZIM2 G24 at 00:20:00): smoothed maximum within 2x of clean;
//  - a clock file of another day (CCJ2's WUM CLK with ZIM2), a Bias-SINEX .gz cut
//    at 2.5 %, an ANTEX file with a 20 MB line in the receiver block: a named error
//    (ppp_solve exit 1) or problems naming the file (ppp_solve exit 3);
//  - CCJ2 observations shifted by 2 h against their products: no fix from either
//    estimator, every epoch with its reason; shifted back by 2 h (another day):
//    the products' window is refused with a named error.
// ppp_solve's exit status (src/tools/ppp_solve.cpp) follows from the outcome: an
// exception is exit 1, no solved epoch is exit 1, problems with a solution exit 3.
#include <gtest/gtest.h>

#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>

#include "ppp_dataset.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "test_support.h"

namespace ppp {
namespace {

/// Mean and max 3D error [m] of the three solutions of a run ("ekf",
/// "smoother_filtered", "smoother_smoothed"), with the epochs solved.
struct Figures {
  std::map<std::string, ErrorSummary> by_tag;
  std::map<std::string, const PppRunSummary*> runs;  // by estimator
  std::vector<PppSolveOutcome> outcomes;
};

Figures solveBoth(PppSolveRequest request) {
  Figures f;
  f.outcomes = solvePppEstimators(request);
  for (const auto& o : f.outcomes) {
    for (const auto& out : o.outputs)
      if (out.statistics) f.by_tag[out.tag] = out.statistics->all;
  }
  for (const auto& o : f.outcomes) f.runs[o.run.estimator] = &o.run;
  return f;
}

std::string describe(const Figures& f) {
  std::ostringstream os;
  os.precision(3);
  for (const auto& [tag, s] : f.by_tag)
    os << tag << " mean " << s.mean_m * 100 << " cm max " << s.max_m * 100 << " cm (" << s.count << " epochs); ";
  return os.str();
}

/// The ZIM2 hour's request of the "within 2x of clean" tests, clean and broken
/// alike, without the tropospheric gradients (the configuration the 2x targets were
/// set with). With them (the default) the clean smoothed solution gains more than
/// the broken ones: smoothed mean clean 3.61 -> 2.59 cm, G15 +1 m 5.37 -> 5.22 cm,
/// G15 without product checks 5.51 -> 5.36 cm (max 10.8 -> 11.0 against a clean
/// 5.9 -> 4.6 cm), so the ratio to clean, not the broken run, moves past 2.
PppSolveRequest zim2Request(const test::PppDataset& zim2, const std::filesystem::path& out) {
  PppSolveRequest r = test::solveRequest(zim2, out.string(), "both");
  r.config.model.estimate_troposphere_gradients = false;
  return r;
}

/// The clean ZIM2 hour, solved once per test binary.
const Figures& cleanZim2() {
  static const Figures clean = [] {
    const auto dir = test::tempDir("integrity_clean_zim2");
    return solveBoth(zim2Request(test::zim2Dataset(), dir / "out"));
  }();
  return clean;
}

/// `src` copied to `dst` with line `line` (1-based) edited: `from` (which must
/// be on that line) replaced by `to`. Returns false when the line does not hold it.
bool copyWithLineEdited(const std::string& src, const std::string& dst, int line, const std::string& from,
                        const std::string& to) {
  std::ifstream in(src, std::ios::binary);
  std::ofstream out(dst, std::ios::binary);
  std::string text;
  bool edited = false;
  for (int n = 1; std::getline(in, text); ++n) {
    if (n == line) {
      const auto at = text.find(from);
      if (at == std::string::npos) return false;
      text.replace(at, from.size(), to);
      edited = true;
    }
    out << text << '\n';
  }
  return edited && static_cast<bool>(out);
}

/// Every solution of `bad` within `factor` times the clean one, in mean and max.
void expectWithinFactor(const Figures& bad, const Figures& clean, double factor, const std::string& what) {
  ASSERT_EQ(bad.by_tag.size(), 3u) << what;
  for (const auto& [tag, c] : clean.by_tag) {
    const ErrorSummary& b = bad.by_tag.at(tag);
    EXPECT_EQ(b.count, c.count) << what << " " << tag << ": every epoch solved";
    EXPECT_LE(b.mean_m, factor * c.mean_m) << what << " " << tag << ": " << describe(bad);
    EXPECT_LE(b.max_m, factor * c.max_m) << what << " " << tag << ": " << describe(bad);
  }
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

// "Move one SP3 record by 1 m: line 104 of the ZIM2 SP3, G15 X
// 23339.029670 -> 23339.030670": the smoother was 9.25 m (filtered) and 2.7 m
// (smoothed) off with a 3 cm sigma.
PppSolveRequest zim2WithG15Moved(const std::filesystem::path& dir) {
  const test::PppDataset zim2 = test::zim2Dataset();
  const std::string sp3 = (dir / "g15.SP3").string();
  EXPECT_TRUE(copyWithLineEdited(zim2.sp3[0], sp3, 104, "PG15  23339.029670", "PG15  23339.030670"));
  PppSolveRequest r = zim2Request(zim2, dir / "out");
  r.files.sp3 = {sp3};
  return r;
}

TEST(IntegrityOffline, OneBadSp3ValueG15IsFoundAndBothEstimatorsStayWithinTwiceClean) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_g15");
  const Figures bad = solveBoth(zim2WithG15Moved(dir));
  expectWithinFactor(bad, cleanZim2(), 2.0, "SP3 G15 +1 m");
  const std::string problems = joined(bad.runs.at("ekf")->problems);
  EXPECT_NE(problems.find("G15 orbit at 2026-05-13 00:30:00"), std::string::npos) << problems;
  std::filesystem::remove_all(dir);
}

// The same error with the product sanity check off: what the estimators' own
// postfit residual tests catch. Before, the smoother ran none.
TEST(IntegrityOffline, OneBadSp3ValueG15WithoutProductChecksIsCaughtByBothEstimatorsPostfitTests) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_g15_nocheck");
  PppSolveRequest request = zim2WithG15Moved(dir);
  request.files.check_products = false;
  const Figures bad = solveBoth(request);
  std::cout << "SP3 G15 +1 m, product checks off: " << describe(bad) << "\n";
  EXPECT_TRUE(bad.runs.at("ekf")->problems.empty()) << "no product check ran";
  expectWithinFactor(bad, cleanZim2(), 2.0, "SP3 G15 +1 m, product checks off");
  for (const std::string estimator : {"ekf", "smoother"}) {
    const PppRunSummary& run = *bad.runs.at(estimator);
    std::size_t postfit = 0;
    for (const auto& [key, n] : run.rejection_counts)
      if (key.reason == RejectionReason::PostfitCode || key.reason == RejectionReason::PostfitPhase) postfit += n;
    EXPECT_GT(postfit, 0u) << estimator << ": the postfit test rejects the satellite";
  }
  std::filesystem::remove_all(dir);
}

// "A +1 m change on G24 gives an EKF maximum of 20.7 m, 40 times its sigma."
PppSolveRequest zim2WithG24Moved(const std::filesystem::path& dir) {
  const test::PppDataset zim2 = test::zim2Dataset();
  const std::string sp3 = (dir / "g24.SP3").string();
  // Line 113: G24 in the 00:30:00 epoch of the ZIM2 SP3.
  EXPECT_TRUE(copyWithLineEdited(zim2.sp3[0], sp3, 113, "PG24  14694.222813", "PG24  14694.223813"));
  PppSolveRequest r = zim2Request(zim2, dir / "out");
  r.files.sp3 = {sp3};
  return r;
}

TEST(IntegrityOffline, OneBadSp3ValueG24IsFoundAndBothEstimatorsStayWithinTwiceClean) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_g24");
  const Figures bad = solveBoth(zim2WithG24Moved(dir));
  // The issue's target: "within 2x of the clean figures, or the satellite rejected
  // with the reason". G24 is found and never used (its 10-node window always holds
  // the marked node): the EKF and the filtered solution stay within 2x; the
  // smoothed one loses a satellite of the hour (8.6 against 3.6 cm mean), so it is
  // held to its maximum and to the named rejection.
  const Figures& clean = cleanZim2();
  for (const std::string tag : {"ekf", "smoother_filtered"}) {
    EXPECT_LE(bad.by_tag.at(tag).mean_m, 2.0 * clean.by_tag.at(tag).mean_m) << tag << ": " << describe(bad);
    EXPECT_LE(bad.by_tag.at(tag).max_m, 2.0 * clean.by_tag.at(tag).max_m) << tag << ": " << describe(bad);
  }
  EXPECT_LE(bad.by_tag.at("smoother_smoothed").max_m, 2.0 * clean.by_tag.at("smoother_smoothed").max_m)
      << describe(bad);
  for (const auto& [estimator, run] : bad.runs) {
    EXPECT_EQ(run->epochs_solved, 120u) << estimator;
    const std::string problems = joined(run->problems);
    EXPECT_NE(problems.find("G24 orbit at 2026-05-13 00:30:00"), std::string::npos) << problems;
    EXPECT_NE(problems.find("G24 (120 epoch(s), first: model: no orbit"), std::string::npos) << problems;
    EXPECT_EQ(run->rejection_counts.at({RejectionStage::Model, RejectionReason::NoOrbit}), 120u) << estimator;
  }
  std::filesystem::remove_all(dir);
}

// "A 1 us clock jump (one CLK value) is rejected at the jump epoch. The
// interpolated 0.7 m at the next epoch still reaches the smoother: smoothed
// maximum 72 cm."
TEST(IntegrityOffline, AOneMicrosecondClockJumpKeepsTheSmoothedMaximumWithinTwiceClean) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_clk_jump");
  const test::PppDataset zim2 = test::zim2Dataset();
  const std::string clk = (dir / "jump.CLK").string();
  ASSERT_TRUE(copyWithLineEdited(zim2.clk[0], clk, 1563, "AS G24  2026 05 13 00 20  0.000000  2    8.027801499675e-06",
                                 "AS G24  2026 05 13 00 20  0.000000  2    9.027801499675e-06"));
  PppSolveRequest request = zim2Request(zim2, dir / "out");
  request.files.clk = {clk};
  const Figures bad = solveBoth(request);
  const ErrorSummary& smoothed = bad.by_tag.at("smoother_smoothed");
  EXPECT_LE(smoothed.max_m, 2.0 * cleanZim2().by_tag.at("smoother_smoothed").max_m) << describe(bad);
  const std::string problems = joined(bad.runs.at("ekf")->problems);
  EXPECT_NE(problems.find("G24"), std::string::npos) << problems;
  std::filesystem::remove_all(dir);
}

// "A clock file of another day (CCJ2's WUM CLK given with ZIM2): exit 0, silent
// fallback to the SP3 clocks."
TEST(IntegrityOffline, AClockFileOfAnotherDayIsANamedError) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_wrong_day_clk");
  PppSolveRequest request = test::solveRequest(test::zim2Dataset(), (dir / "out").string(), "both");
  request.files.clk = {test::ccj2Dataset().clk[0]};
  try {
    solvePppEstimators(request);
    FAIL() << "a clock file of another day was used";
  } catch (const ParseError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(request.files.clk[0]), std::string::npos) << what;
    EXPECT_NE(what.find("a clock file of another day"), std::string::npos) << what;
  }
  std::filesystem::remove_all(dir);
}

// "A Bias-SINEX .gz truncated at 2.5 %: exit 0, with 7 of 12 satellites silently dropped."
TEST(IntegrityOffline, ATruncatedBiasFileIsAProblemNamingTheFileAndTheSatellitesDropped) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_truncated_bia");
  const test::PppDataset zim2 = test::zim2Dataset();
  const std::string bytes = test::readFileBytes(zim2.bia);
  const std::string truncated = (dir / "truncated.BIA.gz").string();
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() * 25 / 1000);
  PppSolveRequest request = test::solveRequest(zim2, (dir / "out").string(), "both");
  request.files.bias = truncated;
  const Figures f = solveBoth(request);
  for (const auto& [estimator, run] : f.runs) {
    const std::string problems = joined(run->problems);
    EXPECT_GT(run->epochs_solved, 0u) << estimator;  // exit 3: solved, with problems
    EXPECT_NE(problems.find(truncated + ": "), std::string::npos) << estimator << ": " << problems;
    EXPECT_NE(problems.find("satellites never used: "), std::string::npos) << estimator << ": " << problems;
  }
  std::filesystem::remove_all(dir);
}

// "A broken ANTEX block (a 20 MB line) is skipped without a report, and nothing is solved."
TEST(IntegrityOffline, AnAntexFileWithATwentyMegabyteLineIsAProblemNamingTheBlock) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_antex_long_line");
  const test::PppDataset zim2 = test::zim2Dataset();
  const std::string atx = (dir / "long_line.atx").string();
  {
    std::ifstream in(zim2.atx[0], std::ios::binary);
    std::ofstream out(atx, std::ios::binary);
    std::string text;
    bool receiver_block = false;
    for (int n = 1; std::getline(in, text); ++n) {
      out << text << '\n';
      if (text.rfind("TRM59800.00     NONE", 0) == 0 && text.find("TYPE / SERIAL NO") != std::string::npos) {
        out << std::string(20u << 20, 'x') << '\n';  // 20 MB in the receiver antenna's block
        receiver_block = true;
      }
    }
    ASSERT_TRUE(receiver_block) << "TRM59800.00 NONE not found in " << zim2.atx[0];
  }
  PppSolveRequest request = test::solveRequest(zim2, (dir / "out").string(), "ekf");
  request.files.atx = {atx};
  const PppSolveOutcome out = solvePpp(request);
  const std::string problems = joined(out.run.problems);
  EXPECT_NE(problems.find(atx), std::string::npos) << problems;
  EXPECT_NE(problems.find("2 problem(s) while reading"), std::string::npos) << problems;
  EXPECT_NE(problems.find("antenna block starting at line 825 skipped"), std::string::npos) << problems;
  std::filesystem::remove_all(dir);
}

/// The CCJ2 observations with every epoch (and TIME OF FIRST OBS) moved by `hours`.
std::string shiftedCcj2Observations(const std::filesystem::path& dir, int hours) {
  const std::string path = (dir / ("ccj2_shifted_" + std::to_string(hours) + "h.21o")).string();
  std::ifstream in(test::ccj2Dataset().obs, std::ios::binary);
  std::ofstream out(path, std::ios::binary);
  auto shifted = [hours](int y, int mo, int d, int h, int mi) {
    std::tm t{};
    t.tm_year = y - 1900;
    t.tm_mon = mo - 1;
    t.tm_mday = d;
    t.tm_hour = h + hours;
    t.tm_min = mi;
    timegm(&t);  // normalises the fields (UTC calendar, no time zone)
    return t;
  };
  std::string line;
  int epochs = 0;
  while (std::getline(in, line)) {
    int y, mo, d, h, mi;
    char buf[64];
    if (line.rfind("> ", 0) == 0 && std::sscanf(line.c_str(), "> %d %d %d %d %d", &y, &mo, &d, &h, &mi) == 5) {
      const std::tm t = shifted(y, mo, d, h, mi);
      std::snprintf(buf, sizeof buf, "> %04d %02d %02d %02d %02d", t.tm_year + 1900, t.tm_mon + 1, t.tm_mday,
                    t.tm_hour, t.tm_min);
      line = buf + line.substr(18);
      ++epochs;
    } else if (line.find("TIME OF FIRST OBS") != std::string::npos &&
               std::sscanf(line.c_str(), "%d %d %d %d %d", &y, &mo, &d, &h, &mi) == 5) {
      const std::tm t = shifted(y, mo, d, h, mi);
      std::snprintf(buf, sizeof buf, "%6d%6d%6d%6d%6d", t.tm_year + 1900, t.tm_mon + 1, t.tm_mday, t.tm_hour,
                    t.tm_min);
      line = buf + line.substr(30);
    }
    out << line << '\n';
  }
  EXPECT_EQ(epochs, 120) << "the 120 epochs of ../shared/data/README.md";
  return path;
}

// "CCJ2 observations shifted by 2 h against CCJ2 products: the EKF refuses, but
// the smoother publishes an 'ok' fix 6,084 km off with a sigma of 24-31 m."
TEST(IntegrityOffline, ObservationsTwoHoursFromTheirProductsGiveNoFixWithTheReason) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("integrity_shifted_obs");
  PppSolveRequest request = test::solveRequest(test::ccj2Dataset(), (dir / "out").string(), "both");
  request.files.obs = shiftedCcj2Observations(dir, 2);
  const Figures f = solveBoth(request);
  ASSERT_EQ(f.outcomes.size(), 2u);
  for (const auto& o : f.outcomes) {
    EXPECT_EQ(o.run.epochs_solved, 0u) << o.run.estimator << ": " << formatRunReport(o.run);  // exit 1
    EXPECT_EQ(o.run.epochs_no_solution + o.run.epochs_failed, 120u) << o.run.estimator;
    std::size_t with_reason = 0;
    for (const auto& [reason, n] : o.run.no_solution_counts)
      if (reason != NoSolutionReason::None) with_reason += n;
    EXPECT_EQ(with_reason, 120u) << o.run.estimator;
    for (const auto& out : o.outputs)
      for (const auto& e : out.solution) EXPECT_FALSE(e.position_ecef_m.has_value()) << out.tag;
  }

  // Two hours earlier the epochs fall on the day before the products: refused at
  // loading (product day against observation day), the file and window named.
  PppSolveRequest before = test::solveRequest(test::ccj2Dataset(), (dir / "before").string(), "both");
  before.files.obs = shiftedCcj2Observations(dir, -2);
  try {
    solvePppEstimators(before);
    FAIL() << "observations of another day were solved";
  } catch (const ParseError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("products of another day"), std::string::npos) << what;
    EXPECT_NE(what.find("2021-07-28 22:00:00"), std::string::npos) << what;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ppp
