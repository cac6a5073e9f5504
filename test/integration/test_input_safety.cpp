// What comes from input files cannot steer the outputs or the terminal, and inputs
// that do not fit the observations are named before solving: file names taken from
// data stay in the output folder; no orbit and clock products, products of another
// time or of none of the observed satellites and a window without epochs are refused
// with their reason, observed satellites the products lack are named; header text is
// shown printable; a GLONASS channel outside -7..+6 and conflicting duplicate ANTEX
// blocks are refused, naming the file and line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/io/data_file_name.h"
#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/ppp/pipeline/product_coverage.h"
#include "ppp_bayes_tree/ppp/pipeline/product_sources.h"
#include "ppp_dataset.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;

/// `text` with line `number` (1-based) passed through `edit`.
std::string editLine(const std::string& text, std::size_t number, const std::function<std::string(std::string)>& edit) {
  std::istringstream in(text);
  std::string line, out;
  for (std::size_t n = 1; std::getline(in, line); ++n) out += (n == number ? edit(line) : line) + "\n";
  return out;
}

/// A copy of ZIM2's observations (made here, never committed) whose MARKER NAME (line 7) is `marker`.
std::string zim2WithMarker(const fs::path& dir, const std::string& marker) {
  const std::string obs = test::readFileBytes(test::zim2Dataset().obs);
  const std::string edited = editLine(obs, 7, [&](std::string line) {
    EXPECT_EQ(line.substr(0, 4), "ZIM2");
    return marker + std::string(60 - marker.size(), ' ') + line.substr(60);
  });
  const std::string path = (dir / "marker.rnx").string();
  std::ofstream(path, std::ios::binary) << edited;
  return path;
}

/// A ZIM2 EKF request over its first five minutes.
PppSolveRequest shortZim2Request(const std::string& obs, const std::string& out) {
  PppSolveRequest request = test::solveRequest(test::zim2Dataset(), out, "ekf");
  request.files.obs = obs;
  request.files.window.end = test::gpst(2026, 5, 13, 0, 5, 0.0);
  return request;
}

TEST(DataFileName, KeepsOnlySafeCharactersAndNeverLeavesTheFolder) {
  EXPECT_EQ(dataFileName("ZIM2"), "ZIM2");
  EXPECT_EQ(dataFileName("zim2_a-1.b"), "zim2_a-1.b");
  EXPECT_EQ(dataFileName("N/A"), "N_A");
  EXPECT_EQ(dataFileName("../q"), "___q");
  EXPECT_EQ(dataFileName(".hidden"), "_hidden");
  EXPECT_EQ(dataFileName("a\\b c"), "a_b_c");
  EXPECT_EQ(dataFileName("\x1b[2J"), "__2J");
  EXPECT_EQ(dataFileName(""), "station");
  EXPECT_EQ(dataFileName("."), "station");
  EXPECT_EQ(dataFileName(".."), "station");
  EXPECT_EQ(dataFileName("..", "x/y"), "x_y");
}

TEST(InputSafety, AMarkerNameWithAPathWritesInsideTheOutputFolder) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("marker_path");
  const fs::path out = dir / "a" / "b";
  const PppSolveOutcome outcome = solvePpp(shortZim2Request(zim2WithMarker(dir, "../q"), out.string()));
  EXPECT_EQ(outcome.name, "___q");
  EXPECT_EQ(fs::path(outcome.epochs_path).parent_path(), out);
  EXPECT_TRUE(fs::exists(out / "___q_ekf.csv"));
  for (const auto& entry : fs::directory_iterator(dir / "a")) EXPECT_TRUE(entry.is_directory()) << entry.path();
  fs::remove_all(dir);
}

TEST(InputSafety, AMarkerNameWithASlashIsOneFileName) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("marker_na");
  const PppSolveOutcome outcome = solvePpp(shortZim2Request(zim2WithMarker(dir, "N/A"), (dir / "out").string()));
  EXPECT_EQ(outcome.name, "n_a");
  EXPECT_GT(outcome.run.epochs_solved, 0u);
  EXPECT_TRUE(fs::exists(dir / "out" / "n_a_ekf_epochs.csv"));
  fs::remove_all(dir);
}

TEST(InputSafety, NoOrbitAndClockProductsAreRefusedBeforeSolving) {
  EXPECT_FALSE(fileProductInputsProblem(0u).empty());
  EXPECT_NE(fileProductInputsProblem(0u).find("no orbit and clock products"), std::string::npos);
  EXPECT_TRUE(fileProductInputsProblem(kProductSp3 | kProductClk).empty());
  EXPECT_TRUE(fileProductInputsProblem(kProductNav).empty());
  PPP_REQUIRE_SHARED_DATA();
  PppInputFiles files = test::inputFiles(test::zim2Dataset());
  files.sp3.clear();
  files.clk.clear();
  files.bias.reset();
  try {
    PppPipeline pipeline(files, PppConfig{});
    FAIL() << "a run without orbits and clocks was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no orbit and clock products"), std::string::npos) << e.what();
  }
}

TEST(InputSafety, ABiasFileOfAnotherDayIsRefusedNamingBothDays) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("bias_day");
  PppSolveRequest request = shortZim2Request(test::zim2Dataset().obs, (dir / "out").string());
  request.files.bias = test::ccj2Dataset().bia;
  try {
    solvePpp(request);
    FAIL() << "a bias file of 2021 was used for observations of 2026";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("biases (WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz) valid 2021-07-29 00:00:00"),
              std::string::npos) << what;
    EXPECT_NE(what.find("observations 2026-05-13 00:00:00"), std::string::npos) << what;
  }
  fs::remove_all(dir);
}

TEST(InputSafety, ProductsEndingBeforeTheObservationsAreNamed) {
  const GnssTime obs_first = test::gpst(2020, 6, 25, 0, 0, 0.0), obs_last = test::gpst(2020, 6, 25, 23, 59, 30.0);
  ProductTimeSpan orbits{"orbits", "GRG.SP3", obs_first, test::gpst(2020, 6, 25, 23, 45, 0.0)};
  const CoverageFinding partial = checkProductCoverage(orbits, obs_first, obs_last);
  EXPECT_EQ(partial.verdict, CoverageVerdict::Partial);
  EXPECT_EQ(partial.text,
            "orbits (GRG.SP3) end at 2020-06-25 23:45:00 GPS, observations until 2020-06-25 23:59:30 GPS: "
            "epochs after are not solved");
  orbits.last = obs_last;
  EXPECT_EQ(checkProductCoverage(orbits, obs_first, obs_last).verdict, CoverageVerdict::Covered);
  orbits.first = test::gpst(2020, 6, 26);
  orbits.last = test::gpst(2020, 6, 27);
  EXPECT_EQ(checkProductCoverage(orbits, obs_first, obs_last).verdict, CoverageVerdict::NotCovered);
  orbits.first.reset();
  orbits.last.reset();
  EXPECT_EQ(checkProductCoverage(orbits, obs_first, obs_last).verdict, CoverageVerdict::NotCovered);
}

TEST(InputSafety, ObservedSatellitesTheProductsLackAreNamed) {
  const auto sat = [](const char* text) { return *SatelliteId::parse(text); };
  ProductSatellites orbits{"orbits/clocks", "X.SP3, X.CLK", {sat("G01"), sat("G02"), sat("E01")}};
  EXPECT_EQ(checkSatelliteCoverage(orbits, {sat("G01"), sat("E01")}).verdict, CoverageVerdict::Covered);
  EXPECT_EQ(checkSatelliteCoverage(orbits, {}).verdict, CoverageVerdict::Covered);
  const CoverageFinding partial = checkSatelliteCoverage(orbits, {sat("G01"), sat("G04"), sat("E14")});
  EXPECT_EQ(partial.verdict, CoverageVerdict::Partial);
  EXPECT_EQ(partial.text, "orbits/clocks (X.SP3, X.CLK) carry no G04, E14: those satellites are not used");
  const CoverageFinding none = checkSatelliteCoverage(orbits, {sat("G04"), sat("E14")});
  EXPECT_EQ(none.verdict, CoverageVerdict::NotCovered);
  EXPECT_EQ(none.text, "orbits/clocks (X.SP3, X.CLK) carry none of the observed satellites (observed: G04, E14; "
                       "carried: G01, G02, E01)");
  std::vector<std::string> notes;
  applyCoverageFinding(partial, notes);
  EXPECT_EQ(notes, std::vector<std::string>{"coverage: " + partial.text});
  EXPECT_THROW(applyCoverageFinding(none, notes), std::runtime_error);
}

/// A copy of ZIM2's clock file (made here, never committed) without the records of `satellite_prefix`
/// ("AS G05": one satellite, "AS G": every GPS satellite) but those of `kept` ("AS G04").
std::string zim2ClocksWithout(const fs::path& dir, const std::string& satellite_prefix, const std::string& kept = "") {
  std::istringstream in(test::readFileBytes(test::zim2Dataset().clk.front()));
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind(satellite_prefix, 0) != 0 || (!kept.empty() && line.rfind(kept, 0) == 0)) out += line + "\n";
  const std::string path = (dir / "zim2_clocks.clk").string();
  std::ofstream(path, std::ios::binary) << out;
  return path;
}

TEST(InputSafety, AnObservedSatelliteWithoutClocksIsNamedInTheNotes) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("sat_coverage");
  PppInputFiles files = test::inputFiles(test::zim2Dataset());
  files.clk = {zim2ClocksWithout(dir, "AS G05")};  // G05 is observed from the first epoch
  const PppPipeline pipeline(files, PppConfig{});
  const std::vector<std::string> notes = pipeline.notes();
  const std::string expected = "coverage: orbits/clocks (IGS0OPSFIN_20261330000_03H_15M_ORB.SP3, zim2_clocks.clk) "
                               "carry no G05: those satellites are not used";
  EXPECT_NE(std::find(notes.begin(), notes.end(), expected), notes.end()) << "notes lack: " << expected;
  fs::remove_all(dir);
}

TEST(InputSafety, ProductsCarryingNoObservedSatelliteAreRefusedNamingBothLists) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("sat_coverage_none");
  PppInputFiles files = test::inputFiles(test::zim2Dataset());
  files.clk = {zim2ClocksWithout(dir, "AS G", "AS G04")};  // ZIM2 never observes G04
  PppConfig config;
  config.signals.systems_from_products = false;
  config.signals.systems = {GnssSystem::GPS};
  try {
    PppPipeline pipeline(files, config);
    FAIL() << "GPS observations were accepted with clocks of no observed GPS satellite";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("products do not cover the observations: orbits/clocks"), std::string::npos) << what;
    EXPECT_NE(what.find("carry none of the observed satellites (observed: G"), std::string::npos) << what;
    EXPECT_NE(what.find("G05"), std::string::npos) << what;
    EXPECT_NE(what.find("; carried: G04)"), std::string::npos) << what;
  }
  fs::remove_all(dir);
}

TEST(InputSafety, AWindowAfterTheFilesEndIsRefusedWithTheFilesSpan) {
  PPP_REQUIRE_SHARED_DATA();
  PppInputFiles files = test::inputFiles(test::zim2Dataset());
  files.window.start = test::gpst(2026, 5, 13, 2, 0, 0.0);
  try {
    PppPipeline pipeline(files, PppConfig{});
    FAIL() << "a window without epochs was accepted";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--start 2026-05-13 02:00:00 GPS holds no epoch of " + files.obs), std::string::npos) << what;
    EXPECT_NE(what.find("its epochs: 2026-05-13 00:00:00 GPS to 2026-05-13 00:59:30 GPS"), std::string::npos)
        << what;
  }
}

TEST(InputSafety, HeaderTextIsShownPrintable) {
  PppRunSummary run;
  run.notes.push_back("antenna \x1b[2JEVIL NONE");
  run.problems.push_back("marker \x1b]0;title\x07");
  const std::string report = formatRunReport(run);
  EXPECT_EQ(report.find('\x1b'), std::string::npos);
  EXPECT_EQ(report.find('\x07'), std::string::npos);
  EXPECT_NE(report.find("antenna \\x1b[2JEVIL NONE"), std::string::npos) << report;
  FileSummary summary;
  summary.path = "x.rnx";
  summary.facts.push_back("marker \x1b[31mRED");
  const std::string text = formatSummary(summary);
  EXPECT_EQ(text.find('\x1b'), std::string::npos);
  EXPECT_NE(text.find("marker \\x1b[31mRED"), std::string::npos) << text;
}

TEST(InputSafety, AGlonassChannelOutsideTheRangeIsRefusedNamingTheLine) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("glonass_channel");
  const std::string obs = test::readFileBytes(test::ccj2Dataset().obs);
  const std::string edited = editLine(obs, 35, [](std::string line) {
    const std::size_t at = line.find("R05  1");
    EXPECT_NE(at, std::string::npos) << line;
    return line.replace(at, 6, "R05 13");
  });
  const std::string path = (dir / "channel.21o").string();
  std::ofstream(path, std::ios::binary) << edited;
  try {
    RinexObsReader::open(path);
    FAIL() << "channel +13 accepted";
  } catch (const ParseError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("35"), std::string::npos) << what;
    EXPECT_NE(what.find("channel 13 of R05 is outside -7..+6"), std::string::npos) << what;
  }
  GlonassChannels channels;
  EXPECT_TRUE(channels.set(5, 6));
  EXPECT_TRUE(channels.set(5, -7));
  EXPECT_FALSE(channels.set(5, 7));
  EXPECT_FALSE(channels.set(5, 13));
  fs::remove_all(dir);
}

TEST(InputSafety, AGlonassChannelTheNavigationRecordsContradictIsAProblem) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string nav_path = test::fixturePath("rinex_nav/mixed_v304.nav");
  const NavData nav = readRinexNav(nav_path);
  int slot = 0;
  for (int s = 1; s <= GlonassChannels::kMaxSlot && slot == 0; ++s)
    if (nav.glonass_channels.channel(s)) slot = s;
  ASSERT_GT(slot, 0);
  const int broadcast = *nav.glonass_channels.channel(slot);
  GlonassChannels header = nav.glonass_channels;
  header.set(slot, broadcast == 6 ? 5 : broadcast + 1);
  ProductAssemblyInputs in;
  in.nav = {nav_path};
  in.atx = {test::dataPath("antex/igs14_2178_satellites.atx")};
  ASSERT_FALSE(nav.glonass.empty());
  in.first = nav.glonass.front().tb - 900.0;
  in.last = nav.glonass.front().tb + 900.0;
  in.observation_glonass_channels = header;
  const ProductAssembly assembly = ProductAssembly::assemble(in, PppConfig{});
  std::string problems;
  for (const auto& p : assembly.problems()) problems += p + "\n";
  EXPECT_NE(problems.find(SatelliteId{GnssSystem::GLONASS, slot}.toString() + ": channel"), std::string::npos)
      << problems;
  EXPECT_NE(problems.find("the channels conflict"), std::string::npos) << problems;
  in.observation_glonass_channels = nav.glonass_channels;
  const ProductAssembly agreeing = ProductAssembly::assemble(in, PppConfig{});
  for (const auto& p : agreeing.problems()) EXPECT_EQ(p.find("conflict"), std::string::npos) << p;
}

// With one source of channels only, a wrong one shows as a satellite the residual
// tests reject at most epochs: CCJ2's R05 on channel +2 instead of +1 (its GLONASS
// SLOT / FRQ # line 35) is named in the notes; with the right channel it is not.
TEST(InputSafety, AGlonassSatelliteRejectedAtMostEpochsIsNamedAsASuspectChannel) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("glonass_suspect");
  test::PppDataset ccj2 = test::ccj2Dataset();
  ccj2.atx = {test::dataPath("antex/igs14_2178_satellites.atx"), test::dataPath("antex/igs20_zim2_gps_trim.atx")};
  const std::string edited = editLine(test::readFileBytes(ccj2.obs), 35, [](std::string line) {
    const std::size_t at = line.find("R05  1");
    EXPECT_NE(at, std::string::npos) << line;
    return line.replace(at, 6, "R05  2");
  });
  const std::string path = (dir / "ccj22100.21o").string();
  std::ofstream(path, std::ios::binary) << edited;
  auto suspectNotes = [&](const std::string& obs) {
    PppSolveRequest request = test::solveRequest(ccj2, (dir / "out").string(), "ekf");
    request.files.obs = obs;
    std::string found;
    for (const auto& n : solvePpp(request).run.notes)
      if (n.find("wrong frequency channel") != std::string::npos) found += n + "\n";
    return found;
  };
  const std::string wrong = suspectNotes(path);
  EXPECT_NE(wrong.find("R05 (channel +2) rejected by the residual tests"), std::string::npos) << wrong;
  EXPECT_EQ(suspectNotes(ccj2.obs), "");
  fs::remove_all(dir);
}

/// The ANTEX file `path` with a copy of its first satellite block, PCO up changed by `up_mm`, placed first.
std::string antexWithDuplicateFirst(const std::string& path, double up_mm) {
  const std::string text = test::readFileBytes(path);
  const std::size_t header_end = text.find("\n", text.find("END OF HEADER")) + 1;
  std::size_t start = text.find("START OF ANTENNA");
  while (text.find("BLOCK", start) > text.find("END OF ANTENNA", start)) start = text.find("START OF ANTENNA", start + 1);
  start = text.rfind('\n', start) + 1;
  const std::size_t end = text.find("\n", text.find("END OF ANTENNA", start)) + 1;
  std::string block = text.substr(start, end - start);
  const std::size_t neu = block.find("NORTH / EAST / UP");
  const std::size_t line = block.rfind('\n', neu) + 1;
  const double up = std::stod(block.substr(line + 20, 10));
  char field[16];
  std::snprintf(field, sizeof field, "%10.2f", up + up_mm);
  block.replace(line + 20, 10, field);
  return text.substr(0, header_end) + block + text.substr(header_end);
}

TEST(InputSafety, ConflictingDuplicateAntexBlocksAreRefusedNamingBothLines) {
  PPP_REQUIRE_SHARED_DATA();
  const fs::path dir = test::tempDir("antex_duplicate");
  const std::string source = test::dataPath("antex/igs20_zim2_gps_trim.atx");
  const std::string conflicting = (dir / "conflicting.atx").string();
  std::ofstream(conflicting, std::ios::binary) << antexWithDuplicateFirst(source, 500.0);
  try {
    readAntexFile(conflicting);
    FAIL() << "two different blocks of one satellite were accepted";
  } catch (const ParseError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(conflicting), std::string::npos) << what;
    EXPECT_NE(what.find("conflicts with the block at line"), std::string::npos) << what;
  }
  const std::string identical = (dir / "identical.atx").string();
  std::ofstream(identical, std::ios::binary) << antexWithDuplicateFirst(source, 0.0);
  EXPECT_NO_THROW(readAntexFile(identical));
  EXPECT_NO_THROW(readAntexFile(source));
  EXPECT_NO_THROW(readAntexFile(test::dataPath("antex/igs14_2178_satellites.atx")));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ppp
