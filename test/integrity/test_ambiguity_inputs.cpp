// Integrity regression suite, ambiguity inputs: the phase information that AR fixes
// on is checked, counted and named (io/bias_bounds.h), clean and faulty input side
// by side. The faulty inputs are made here at run time from the real files of
// ../shared/data (never committed):
//  - the WUM Bias-SINEX of CCJ2 with every phase OSB set to 1e6 ns: each row a
//    problem naming the file and line and the bound, none used, the AR gate float
//    with PhaseInformationRefused (clean: fixing on the WUM OSBs);
//  - the same file with a conflicting duplicate of one row (G05 L1C): both lines
//    named, neither used, the other satellites kept; a repeat of the same value is
//    counted and the row kept;
//  - the GRG clock header of ESBC with wide-lane values of 1e300 or 12345.678 or
//    garbage: each refused line named with its file line; when none is left, the
//    gate says why (clean: fixing on the 66 wide-lane biases);
//  - the WUM bias and clock files renamed (no IGS long product name): the same gate,
//    decided from the header fields (clock "PGM / RUN BY" WHU, Bias-SINEX agency WHU);
//  - SSR phase biases beyond the bound in an RTCM 1265 stream: refused with the byte
//    offset and frame, the plausible one kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "ppp_dataset.h"
#include "ppp_bayes_tree/io/bias_bounds.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "test_support.h"

namespace ppp {
namespace {

const std::string kWumBias = "ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz";
const std::string kGrgClock = "esbc-2020-177/GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz";

/// Copies a shared file (plain or gzip) line by line to `to` (plain), each line
/// through `edit` (its 1-based line number given); returns the lines `edit` changed.
std::vector<std::size_t> copyEdited(const std::string& from, const std::string& to,
                                    const std::function<bool(std::size_t, std::string&)>& edit) {
  auto src = openLineSource(from);
  std::ofstream out(to);
  std::string line;
  std::vector<std::size_t> changed;
  for (std::size_t n = 1; src->next(line); ++n) {
    if (edit(n, line)) changed.push_back(n);
    out << line << '\n';
  }
  return changed;
}

/// A test's directory of made inputs (copies of the shared files, up to 18 MB each),
/// removed when the test ends.
struct MadeInputs {
  explicit MadeInputs(const std::string& tag) : dir(test::tempDir(tag)) {}
  ~MadeInputs() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
  std::filesystem::path operator/(const std::string& name) const { return dir / name; }
  std::filesystem::path dir;
};

bool isSatellitePhaseOsb(const std::string& line) {
  return line.rfind(" OSB ", 0) == 0 && line.size() > 90 && line[25] == 'L' && line[11] != ' ';
}

/// CCJ2's WUM products with the IGS14 satellite antennas, `bias` and `clk` in place of WUM's.
ProductAssemblyInputs ccj2Inputs(const std::string& bias, const std::string& clk) {
  const test::PppDataset d = test::ccj2Dataset();
  ProductAssemblyInputs in;
  in.sp3 = d.sp3;
  in.clk = {clk};
  in.bias = bias;
  in.atx = {test::dataPath("antex/igs14_2178_satellites.atx"), test::dataPath("antex/igs20_zim2_gps_trim.atx")};
  return in;
}

bool anyContains(const std::vector<std::string>& texts, const std::string& part) {
  return std::any_of(texts.begin(), texts.end(), [&](const std::string& t) { return t.find(part) != std::string::npos; });
}

TEST(AmbiguityInputs, PhaseOsbsOfAbsurdMagnitudeAreRefusedWithTheirLineAndTheGateSaysWhy) {
  PPP_REQUIRE_SHARED_DATA();
  const MadeInputs dir("ambiguity_inputs_osb");
  const std::string faulty = (dir / "WUM0MGXRAP_20212100000_01D_01D_ABS.BIA").string();
  const std::vector<std::size_t> edited = copyEdited(test::dataPath(kWumBias), faulty, [](std::size_t, std::string& l) {
    if (!isSatellitePhaseOsb(l)) return false;
    l.replace(70, 21, "      1000000.0000000");  // VALUE, columns 71-91
    return true;
  });
  ASSERT_EQ(edited.size(), 298u);  // every satellite phase OSB of the file

  // The reader: every edited row refused with its line and the bound; counted.
  const BiasSinexFile clean_file = readBiasSinexFile(test::dataPath(kWumBias));
  EXPECT_TRUE(clean_file.report.clean()) << clean_file.report.summary();
  EXPECT_EQ(clean_file.refused.beyond_bound, 0u);
  const BiasSinexFile file = readBiasSinexFile(faulty);
  EXPECT_EQ(file.refused.beyond_bound, 298u);
  EXPECT_EQ(file.refused.phase_rows, 298u);
  EXPECT_EQ(file.report.problemCount(), 298u);
  ASSERT_FALSE(file.report.problems().empty());
  EXPECT_EQ(file.report.problems().front().line, edited.front());
  EXPECT_EQ(file.report.problems().front().reason, "phase bias 1e+06 ns beyond the bound of 100 ns: row not used");
  EXPECT_EQ(clean_file.records.size() - file.records.size(), 298u);  // the code OSBs stay

  // The gate: clean fixes on the WUM OSBs; faulty stays float and says why.
  const std::string clk = test::ccj2Dataset().clk.front();
  const ProductAssembly clean = ProductAssembly::assemble(ccj2Inputs(test::dataPath(kWumBias), clk), PppConfig{});
  EXPECT_TRUE(clean.arGate().fix) << clean.arGate().text();
  EXPECT_EQ(clean.arGate().phase, PhaseInformation::AnalysisCentreOsb);
  const ProductAssembly bad = ProductAssembly::assemble(ccj2Inputs(faulty, clk), PppConfig{});
  EXPECT_FALSE(bad.arGate().fix);
  EXPECT_EQ(bad.arGate().reason, ArGateReason::PhaseInformationRefused);
  EXPECT_EQ(bad.phaseBiases(), nullptr);
  // Only the GPS and Galileo rows are read (the systems processed).
  EXPECT_NE(bad.arGate().text().find("phase bias rows of WUM0MGXRAP_20212100000_01D_01D_ABS.BIA refused as "
                                     "implausible (first: line "),
            std::string::npos)
      << bad.arGate().text();
  EXPECT_TRUE(anyContains(bad.problems(), "WUM0MGXRAP_20212100000_01D_01D_ABS.BIA: ")) << bad.problems().front();
  EXPECT_TRUE(anyContains(bad.problems(), "beyond the bound of 100 ns"));
}

TEST(AmbiguityInputs, ConflictingDuplicateBiasSinexRowsAreReportedWithBothLinesAndNeitherIsUsed) {
  PPP_REQUIRE_SHARED_DATA();
  const MadeInputs dir("ambiguity_inputs_duplicates");
  const std::string conflicting = (dir / "conflicting.bia").string(), repeated = (dir / "repeated.bia").string();
  std::size_t original = 0;
  std::string row;
  copyEdited(test::dataPath(kWumBias), (dir / "probe.bia").string(), [&](std::size_t n, std::string& l) {
    if (original == 0 && isSatellitePhaseOsb(l) && l.substr(11, 3) == "G05" && l.substr(25, 3) == "L1C") {
      original = n;
      row = l;
    }
    return false;
  });
  ASSERT_NE(original, 0u) << "no G05 L1C phase OSB in " << kWumBias;
  // The duplicate right after the original: 0.5 ns more (conflict), or the same value (repeat).
  std::string other = row;
  other.replace(70, 21, "            0.5000000");
  const auto insertAfterOriginal = [&](const std::string& extra) {
    return [&, extra](std::size_t n, std::string& l) {
      if (n == 1) l.replace(l.find("00001072"), 8, "00001073");  // the header counts the added row
      if (n != original) return false;
      l += "\n" + extra;
      return true;
    };
  };
  copyEdited(test::dataPath(kWumBias), conflicting, insertAfterOriginal(other));
  copyEdited(test::dataPath(kWumBias), repeated, insertAfterOriginal(row));

  const SatelliteId g05{GnssSystem::GPS, 5};
  const ObservationCode l1c = *ObservationCode::parse("L1C");
  const GnssTime t = test::gpst(2021, 7, 29, 0, 30, 0);
  const BiasSinexFile clean = readBiasSinexFile(test::dataPath(kWumBias));
  ASSERT_TRUE(clean.osb(g05, l1c, t).has_value());

  const BiasSinexFile c = readBiasSinexFile(conflicting);
  ASSERT_EQ(c.report.problemCount(), 1u) << c.report.summary();
  EXPECT_EQ(c.report.problems().front().line, original + 1);
  EXPECT_NE(c.report.problems().front().reason.find("OSB G05 L1C conflicts with line " + std::to_string(original)),
            std::string::npos)
      << c.report.problems().front().reason;
  EXPECT_NE(c.report.problems().front().reason.find("neither row used"), std::string::npos);
  EXPECT_EQ(c.refused.conflicting, 2u);
  EXPECT_FALSE(c.osb(g05, l1c, t).has_value());                 // neither value
  EXPECT_TRUE(c.osb(g05, *ObservationCode::parse("C1C"), t));   // the satellite's other rows stay
  EXPECT_TRUE(c.osb(SatelliteId{GnssSystem::GPS, 7}, l1c, t));  // and the other satellites'

  const BiasSinexFile r = readBiasSinexFile(repeated);
  EXPECT_TRUE(r.report.clean()) << r.report.summary();
  EXPECT_EQ(r.report.counters().at("repeated rows (same value) ignored"), 1u);
  ASSERT_TRUE(r.osb(g05, l1c, t).has_value());
  EXPECT_EQ(r.osb(g05, l1c, t)->value, clean.osb(g05, l1c, t)->value);
  EXPECT_EQ(r.osb(g05, l1c, t)->line, original);
}

/// The GRG clock header's "WL" lines through `edit_value` (the value field, or the whole line).
RinexClockHeader grgHeaderEdited(const std::string& path, const std::function<void(std::string&)>& edit) {
  std::vector<std::size_t> wl;
  copyEdited(test::dataPath(kGrgClock), path, [&](std::size_t, std::string& l) {
    if (l.rfind("WL ", 0) != 0) return false;
    edit(l);
    return true;
  });
  return readRinexClockHeader(path);
}

void setWideLaneValue(std::string& line, const std::string& value) {
  // "WL G01 2020   6 25 12  0  0.000000  1   -4.400000E-01  0105 ... COMMENT": the 10th field.
  std::size_t pos = 0;
  for (int field = 0; field < 9; ++field) {
    pos = line.find_first_not_of(' ', pos);
    pos = line.find(' ', pos);
  }
  const std::size_t begin = line.find_first_not_of(' ', pos), end = line.find(' ', begin);
  std::string padded = value;
  padded.resize(std::max(padded.size(), end - begin), ' ');
  line.replace(begin, end - begin, padded.substr(0, end - begin));
}

TEST(AmbiguityInputs, WideLaneValuesBeyondTheBoundAndGarbageLinesAreRefusedWithTheirLine) {
  PPP_REQUIRE_SHARED_DATA();
  const MadeInputs dir("ambiguity_inputs_wl");
  const std::string clean_clk = test::dataPath(kGrgClock);
  const IntegerRecoveryClockBiases clean = readIntegerRecoveryClockBiases({readRinexClockHeader(clean_clk)}, {clean_clk});
  ASSERT_NE(clean.provider, nullptr);
  EXPECT_EQ(clean.provider->size(), 66u);
  EXPECT_EQ(clean.refused, 0u);

  // One satellite at 12345.678 cycles: refused with its line, the 65 others kept.
  const std::string one = (dir / "one.clk").string();
  bool first = true;
  const RinexClockHeader h1 = grgHeaderEdited(one, [&](std::string& l) {
    if (first) setWideLaneValue(l, "12345.678");
    first = false;
  });
  const IntegerRecoveryClockBiases r1 = readIntegerRecoveryClockBiases({h1}, {one});
  ASSERT_NE(r1.provider, nullptr);
  EXPECT_EQ(r1.provider->size(), 65u);
  ASSERT_EQ(r1.problems.size(), 1u);
  EXPECT_EQ(r1.problems.front().rfind("one.clk: line 132 \"WL E01 ", 0), 0u) << r1.problems.front();
  EXPECT_NE(r1.problems.front().find("wide-lane bias 12345.7 cycles beyond the bound of 5 cycles: not used"),
            std::string::npos)
      << r1.problems.front();

  // Every value 1e300, or every line garbage: nothing left, and why.
  for (const auto& [name, edit] : std::vector<std::pair<std::string, std::function<void(std::string&)>>>{
           {"huge.clk", [](std::string& l) { setWideLaneValue(l, "1e300"); }},
           {"garbage.clk", [](std::string& l) { l.replace(7, 30, std::string(30, '#')); }}}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    const IntegerRecoveryClockBiases r = readIntegerRecoveryClockBiases({grgHeaderEdited(path, edit)}, {path});
    EXPECT_EQ(r.provider, nullptr);
    EXPECT_EQ(r.lines, 66u);
    EXPECT_EQ(r.refused, 66u);
    EXPECT_EQ(r.whyNone().rfind("all 66 wide-lane lines of the clock header refused (first: " + name + ": line 132 ", 0),
              0u)
        << r.whyNone();
  }
}

TEST(AmbiguityInputs, AClockHeaderWithoutUsableWideLanesKeepsTheRunFloatAndSaysWhy) {
  PPP_REQUIRE_SHARED_DATA();
  const MadeInputs dir("ambiguity_inputs_wl_gate");
  const std::string huge = (dir / "GRG0MGXFIN_20201770000_01D_30S_CLK.CLK").string();
  grgHeaderEdited(huge, [](std::string& l) { setWideLaneValue(l, "1e300"); });
  ProductAssemblyInputs in;
  in.sp3 = {test::dataPath("esbc-2020-177/GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz")};
  in.atx = {test::dataPath("antex/igs14_2178_satellites.atx"), test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
  in.first = test::gpst(2020, 6, 25, 0, 0, 0);
  in.last = test::gpst(2020, 6, 25, 1, 0, 0);
  in.clk = {test::dataPath(kGrgClock)};
  const ProductAssembly clean = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_TRUE(clean.arGate().fix) << clean.arGate().text();
  EXPECT_EQ(clean.arGate().phase, PhaseInformation::IntegerRecoveryClocks);

  in.clk = {huge};
  const ProductAssembly a = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_FALSE(a.arGate().fix);
  EXPECT_EQ(a.arGate().reason, ArGateReason::PhaseInformationRefused);
  EXPECT_EQ(a.arGate().text().rfind("ambiguity resolution: float (enabled: auto): phase information refused as "
                                    "implausible (all 66 wide-lane lines of the clock header refused (first: "
                                    "GRG0MGXFIN_20201770000_01D_30S_CLK.CLK: line 132 ",
                                    0),
            0u)
      << a.arGate().text();
  EXPECT_EQ(a.problems().size(), 66u);
  EXPECT_FALSE(a.config().ambiguity_resolution.enabled);
}

TEST(AmbiguityInputs, RenamedWumFilesGiveTheSameGateFromTheirHeaders) {
  PPP_REQUIRE_SHARED_DATA();
  const MadeInputs dir("ambiguity_inputs_renamed");
  const std::string bias = (dir / "phase_biases_ccj2.bia").string(), clk = (dir / "clocks_ccj2.clk").string();
  copyEdited(test::dataPath(kWumBias), bias, [](std::size_t, std::string&) { return false; });
  copyEdited(test::ccj2Dataset().clk.front(), clk, [](std::size_t, std::string&) { return false; });
  const ProductAssembly original =
      ProductAssembly::assemble(ccj2Inputs(test::dataPath(kWumBias), test::ccj2Dataset().clk.front()), PppConfig{});
  for (const auto& [b, c] : std::vector<std::pair<std::string, std::string>>{
           {bias, test::ccj2Dataset().clk.front()}, {test::dataPath(kWumBias), clk}, {bias, clk}}) {
    SCOPED_TRACE(b + " " + c);
    const ProductAssembly renamed = ProductAssembly::assemble(ccj2Inputs(b, c), PppConfig{});
    EXPECT_EQ(renamed.arGate().fix, original.arGate().fix);
    EXPECT_EQ(renamed.arGate().reason, original.arGate().reason);
    EXPECT_EQ(renamed.arGate().text(), original.arGate().text());
  }
  EXPECT_EQ(original.arGate().text(),
            "ambiguity resolution: fixing (enabled: auto): phase OSBs of the clocks' analysis centre (WHU, from the "
            "headers)");
}

SsrMessage gpsPhaseBiasMessage(double g01_bias_m, double g02_bias_m) {
  SsrMessage m;
  m.header.system = GnssSystem::GPS;
  m.header.kind = SsrMessageKind::PhaseBias;
  m.header.epoch_time_s = 3600;
  m.header.update_interval_code = 2;
  for (const auto& [prn, bias_m] : {std::pair<int, double>{1, g01_bias_m}, {2, g02_bias_m}}) {
    SsrPhaseBias p;
    p.satellite = SatelliteId{GnssSystem::GPS, prn};
    p.biases.push_back({0, ObservationCode::parse("L1C"), true, 2, 0, bias_m});
    m.phase_biases.push_back(p);
  }
  return m;
}

TEST(AmbiguityInputs, SsrPhaseBiasesBeyondTheBoundAreRefusedWithTheirFrame) {
  // RTCM 1265's DF482 reaches +-52.4 m; 40 m (133 ns) is beyond the 100 ns bound, 1.2345 m is not.
  std::vector<std::uint8_t> bytes = encodeSsrFrame(gpsPhaseBiasMessage(1.2345, -0.5));
  const std::vector<std::uint8_t> faulty = encodeSsrFrame(gpsPhaseBiasMessage(1.2345, 40.0));
  bytes.insert(bytes.end(), faulty.begin(), faulty.end());
  RtcmSsrDecoder decoder(test::gpst(2026, 7, 7, 0, 0, 0));
  Rtcm3Framer framer;
  framer.feed(bytes.data(), bytes.size(), [&](const Rtcm3Frame& f) { decoder.decode(f); });
  const std::vector<SsrMessage> messages = decoder.takeMessages();
  ASSERT_EQ(messages.size(), 2u);
  ASSERT_EQ(messages[0].phase_biases.size(), 2u);
  EXPECT_EQ(messages[0].phase_biases[1].biases.size(), 1u);  // clean: both kept
  EXPECT_NEAR(messages[1].phase_biases[0].biases.at(0).bias_m, 1.2345, 1e-9);
  EXPECT_TRUE(messages[1].phase_biases[1].biases.empty());  // faulty: G02's refused
  const StreamCounters& c = decoder.counters();
  EXPECT_EQ(c.count(StreamProblemKind::ImplausibleValue), 1u);
  ASSERT_EQ(c.problems.size(), 1u);
  EXPECT_EQ(c.problems.front().frame_index, 1u);
  EXPECT_EQ(c.problems.front().byte_offset, bytes.size() - faulty.size());
  EXPECT_NE(c.problems.front().describe().find("G02 signal 0: phase bias 40 m beyond the bound of 29.9792 m (100 ns)"),
            std::string::npos)
      << c.problems.front().describe();
}

}  // namespace
}  // namespace ppp
