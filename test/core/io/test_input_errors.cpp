// Input errors that must name the file and say what is wrong: a
// directory given where a file is expected is "a directory", never an "empty file".
#include <gtest/gtest.h>

#include <filesystem>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "test_support.h"

namespace ppp {
namespace {

TEST(InputErrors, ADirectoryIsNamedAsADirectory) {
  const auto dir = test::tempDir("input_errors");
  for (const auto& open : {+[](const std::string& p) { openLineSource(p); },
                           +[](const std::string& p) { RinexObsReader::open(p); }}) {
    try {
      open(dir.string());
      FAIL() << "a directory opened as a file";
    } catch (const FileOpenError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(dir.string()), std::string::npos) << what;
      EXPECT_NE(what.find("is a directory"), std::string::npos) << what;
      EXPECT_EQ(what.find("empty file"), std::string::npos) << what;
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ppp

#include <fstream>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_dataset.h"

namespace ppp {
namespace {

// A Bias-SINEX .gz cut at 2.5 % of its bytes used to run through with
// exit 0 and 7 of the 12 satellites silently dropped. Now the run's problems name
// the file and what its reader found, and the satellites the run never used.
TEST(InputErrors, ATruncatedBiasFileIsAProblemOfTheRunNamingTheSatellitesDropped) {
  PPP_REQUIRE_SHARED_DATA();
  const auto dir = test::tempDir("truncated_bia");
  const test::PppDataset zim2 = test::zim2Dataset();
  const std::string bytes = test::readFileBytes(zim2.bia);
  const std::string truncated = (dir / "truncated.BIA.gz").string();  // a copy made here, never committed
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() * 25 / 1000);
  PppSolveRequest request = test::solveRequest(zim2, (dir / "out").string(), "ekf");
  request.files.bias = truncated;
  const PppSolveOutcome outcome = solvePpp(request);
  std::string problems;
  for (const auto& p : outcome.run.problems) problems += p + "\n";
  EXPECT_NE(problems.find(truncated + ": "), std::string::npos) << problems;
  EXPECT_NE(problems.find("problem(s) while reading"), std::string::npos) << problems;
  EXPECT_NE(problems.find("satellites never used: "), std::string::npos) << problems;
  EXPECT_NE(problems.find("no OSB"), std::string::npos) << problems;

  // The clean file: no problem at all.
  PppSolveRequest clean = test::solveRequest(zim2, (dir / "clean").string(), "ekf");
  EXPECT_TRUE(solvePpp(clean).run.problems.empty());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ppp
