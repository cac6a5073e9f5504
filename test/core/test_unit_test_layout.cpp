// The unit tests mirror the parts of the core (test/README.md, "Where a test goes"):
// every folder below test/core is a part of src/core (the same sub-path), and every
// test file in it includes a header of that part, itself or through a test helper it
// includes (a helper beside it, in test/support or test/fuzz). A planted test in a
// folder with no part, and one that tests another part, make the check fail.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The quoted includes of a source text.
std::vector<std::string> quotedIncludes(const std::string& text) {
  static const std::regex include(R"re(^\s*#\s*include\s+"([^"]+)")re", std::regex::multiline);
  std::vector<std::string> out;
  for (std::sregex_iterator it(text.begin(), text.end(), include), end; it != end; ++it) out.push_back((*it)[1]);
  return out;
}

/// The includes of a test file and of the test helpers it includes (one level):
/// a helper is looked for beside the file, in test/ and in test/support/.
std::set<std::string> includesThroughHelpers(const fs::path& file, const fs::path& test_dir) {
  std::set<std::string> all;
  for (const std::string& inc : quotedIncludes(readText(file))) {
    all.insert(inc);
    if (inc.rfind("ppp_bayes_tree/", 0) == 0) continue;
    for (const fs::path& dir : {file.parent_path(), test_dir, test_dir / "support"}) {
      if (!fs::is_regular_file(dir / inc)) continue;
      for (const std::string& nested : quotedIncludes(readText(dir / inc))) all.insert(nested);
      break;
    }
  }
  return all;
}

/// What is wrong with the unit test layout below `test_dir`/core against
/// `src_core`: one line per folder without a part and per file that includes no
/// header of its part.
std::vector<std::string> layoutProblems(const fs::path& test_dir, const fs::path& src_core) {
  std::vector<std::string> problems;
  const fs::path core = test_dir / "core";
  for (const auto& entry : fs::recursive_directory_iterator(core)) {
    const fs::path& p = entry.path();
    const std::string part = fs::relative(entry.is_directory() ? p : p.parent_path(), core).generic_string();
    if (entry.is_directory()) {
      if (!fs::is_directory(src_core / part)) problems.push_back("test/core/" + part + ": no part src/core/" + part);
      continue;
    }
    const std::string name = p.filename().string();
    if (part == "." || name.rfind("test_", 0) != 0 || p.extension() != ".cpp") continue;
    const std::string wanted = "ppp_bayes_tree/" + part + "/";
    bool found = false;
    for (const std::string& inc : includesThroughHelpers(p, test_dir)) found = found || inc.rfind(wanted, 0) == 0;
    if (!found) problems.push_back("test/core/" + part + "/" + name + ": includes no header of " + wanted);
  }
  return problems;
}

TEST(UnitTestLayout, EveryFolderIsAPartAndEveryTestIncludesItsPart) {
  const fs::path repo = PPP_REPO_DIR;
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(repo / "test" / "core"))
    if (entry.is_regular_file() && entry.path().filename().string().rfind("test_", 0) == 0) ++files;
  EXPECT_GT(files, 80u);  // the walk found the unit tests
  for (const std::string& problem : layoutProblems(repo / "test", repo / "src" / "core")) ADD_FAILURE() << problem;
}

TEST(UnitTestLayout, APlantedMisplacedTestIsFound) {
  const fs::path root = fs::temp_directory_path() / ("unit_test_layout_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "src" / "core" / "io" / "rtcm");
  fs::create_directories(root / "test" / "core" / "io" / "rtcm");
  fs::create_directories(root / "test" / "support");
  const auto write = [&](const fs::path& path, const std::string& text) { std::ofstream(path) << text; };
  // In place: directly, and through a helper in test/support.
  write(root / "test" / "core" / "io" / "rtcm" / "test_framer.cpp", "#include \"ppp_bayes_tree/io/rtcm/framer.h\"\n");
  write(root / "test" / "support" / "rtcm_helper.h", "#include \"ppp_bayes_tree/io/rtcm/msm.h\"\n");
  write(root / "test" / "core" / "io" / "rtcm" / "test_msm.cpp", "#include \"rtcm_helper.h\"\n");
  EXPECT_TRUE(layoutProblems(root / "test", root / "src" / "core").empty());
  // Misplaced: a test of another part, and a folder that is no part.
  fs::create_directories(root / "test" / "core" / "estimators");
  write(root / "test" / "core" / "io" / "rtcm" / "test_ubx.cpp", "#include \"ppp_bayes_tree/io/ubx/ubx_decoder.h\"\n");
  const std::vector<std::string> problems = layoutProblems(root / "test", root / "src" / "core");
  fs::remove_all(root);
  ASSERT_EQ(problems.size(), 2u);
  std::set<std::string> sorted(problems.begin(), problems.end());
  EXPECT_EQ(*sorted.begin(), "test/core/estimators: no part src/core/estimators");
  EXPECT_EQ(*sorted.rbegin(), "test/core/io/rtcm/test_ubx.cpp: includes no header of ppp_bayes_tree/io/rtcm/");
}

}  // namespace
