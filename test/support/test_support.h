#pragma once
// Shared helpers for the unit tests.
//
// Real datasets live in ../shared/data beside the repository (never copied into
// it). PPP_SHARED_DATA in the environment overrides the compiled-in default.
// Tests that need the data call PPP_REQUIRE_SHARED_DATA(), which skips the test
// with the reason when the directory is absent, so the run reports it as skipped.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp::test {

inline std::string sharedDataDir() {
  if (const char* env = std::getenv("PPP_SHARED_DATA"); env != nullptr && *env != '\0') return env;
  return PPP_DEFAULT_SHARED_DATA;
}

inline bool sharedDataAvailable() {
  return std::filesystem::is_directory(sharedDataDir() + "/zim2-2026-133");
}

/// Path of a file below ../shared/data, e.g. dataPath("zim2-2026-133/X.rnx").
inline std::string dataPath(const std::string& relative) { return sharedDataDir() + "/" + relative; }

/// Path of a fixture committed under test/fixtures.
inline std::string fixturePath(const std::string& relative) {
  return std::string(PPP_FIXTURE_DIR) + "/" + relative;
}

inline std::string readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// Writes `bytes` to `path` (binary, replacing the file).
inline void writeFileBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// A calendar date and time read in `system` (GPS by default), as a GnssTime.
inline GnssTime gpst(int year, int month, int day, int hour = 0, int minute = 0, double second = 0.0,
                     TimeSystem system = TimeSystem::GPS) {
  return GnssTime::fromCalendar(CalendarTime{year, month, day, hour, minute, second}, system);
}

/// A fresh empty temporary directory for one test.
inline std::filesystem::path tempDir(const std::string& tag) {
  auto dir = std::filesystem::temp_directory_path() /
             ("ppp_test_" + tag + "_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
              "_" + std::to_string(std::rand()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace ppp::test

#define PPP_REQUIRE_SHARED_DATA()                                                               \
  do {                                                                                          \
    if (!::ppp::test::sharedDataAvailable()) {                                                  \
      GTEST_SKIP() << "shared dataset not found at " << ::ppp::test::sharedDataDir()            \
                   << " (set PPP_SHARED_DATA or place ../shared/data beside the repository)"; \
    }                                                                                           \
  } while (0)
