// Input errors that must name the file and say what is wrong (issue 16): a
// directory given where a file is expected is "a directory", never an "empty file".
#include <gtest/gtest.h>

#include <filesystem>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex_obs_reader.h"
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
