// Signal selection for the IF model: code/phase priorities on the real ZIM2 and
// CCJ2 epochs, Bias-SINEX OSB alignment (rows cited), the no-bias-file report,
// LLI mapping, phase-shift handling and skip reasons.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/models/sinex_bias_provider.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

namespace ppp {
namespace {

const char* kZim2Obs = "zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx";
const char* kZim2Bia = "zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz";
const char* kCcj2Obs = "ccj2-2021-210/ccj22100.21o";
const char* kCcj2Bia = "ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz";

SatelliteId sat(const char* s) { return *SatelliteId::parse(s); }
ObservationCode code(const char* s) { return *ObservationCode::parse(s); }
double ns(double v) { return v * 1e-9 * kSpeedOfLight_mps; }

/// The selected signals and carrier frequencies of one observation.
void expectSignals(const DualFrequencyObservation& o, GnssSystem system, const char* code1, const char* code2,
                   const char* phase1, const char* phase2, double f1_hz, double f2_hz) {
  EXPECT_EQ(o.satellite.system, system);
  EXPECT_EQ(o.code1, code(code1));
  EXPECT_EQ(o.code2, code(code2));
  EXPECT_EQ(o.phase1, code(phase1));
  EXPECT_EQ(o.phase2, code(phase2));
  EXPECT_DOUBLE_EQ(o.frequency1_hz, f1_hz);
  EXPECT_DOUBLE_EQ(o.frequency2_hz, f2_hz);
}

const DualFrequencyObservation* findObs(const SignalSelectionResult& r, const char* s) {
  for (const auto& o : r.observations) {
    if (o.satellite == sat(s)) return &o;
  }
  return nullptr;
}

TEST(SignalSelection, Zim2GpsPicksC1CC2WWithCodeOsb) {
  PPP_REQUIRE_SHARED_DATA();
  auto reader = RinexObsReader::open(test::dataPath(kZim2Obs));
  const BiasSinexFile bias_file = readBiasSinexFile(test::dataPath(kZim2Bia));
  const SinexBiasProvider bias(bias_file, kZim2Bia);
  ObsEpoch epoch;
  ASSERT_TRUE(reader.next(epoch));
  SignalSelector selector(reader.header(), {}, &bias);
  const auto r = selector.select(epoch);
  // ZIM2 GPS types (header): C1C L1C ... C2S L2S ... C2W L2W ... C5Q: no C1W, so
  // the default priority C1W, C1C gives C1C; C2W and L1C / L2W.
  ASSERT_GE(r.observations.size(), 10u);
  for (const auto& o : r.observations) {
    expectSignals(o, GnssSystem::GPS, "C1C", "C2W", "L1C", "L2W", 1575.42e6, 1227.60e6);
  }
  // Non-GPS satellites are skipped with the reason (default: GPS only).
  bool galileo_skipped = false;
  for (const auto& s : r.skipped) galileo_skipped |= s.satellite.system == GnssSystem::Galileo;
  EXPECT_TRUE(galileo_skipped);
  // COD0OPSFIN_20261330000_01D_01D_OSB.BIA, lines 92 and 97:
  //  OSB  G050 G05  C1C  2026:133:00000 2026:134:00000 ns  -4.8164
  //  OSB  G050 G05  C2W  2026:133:00000 2026:134:00000 ns  -6.7069
  // corrected = observed - OSB (Bias-SINEX 1.00).
  const auto* g05 = findObs(r, "G05");
  ASSERT_NE(g05, nullptr);
  ASSERT_TRUE(g05->code1_osb_m && g05->code2_osb_m);
  EXPECT_NEAR(*g05->code1_osb_m, ns(-4.8164), 1e-9);
  EXPECT_NEAR(*g05->code2_osb_m, ns(-6.7069), 1e-9);
  const auto* raw_c1 = epoch.find(sat("G05"), code("C1C"));
  const auto* raw_c2 = epoch.find(sat("G05"), code("C2W"));
  const auto* raw_l1 = epoch.find(sat("G05"), code("L1C"));
  ASSERT_TRUE(raw_c1 && raw_c2 && raw_l1);
  EXPECT_NEAR(g05->code1_m, *raw_c1->value - ns(-4.8164), 1e-9);
  EXPECT_NEAR(g05->code2_m, *raw_c2->value - ns(-6.7069), 1e-9);
  // Value as written in the file (ZIM2 .rnx line 58: G05 C1C 24817828.909, L1C 130418582.443).
  EXPECT_NEAR(*raw_c1->value, 24817828.909, 1e-6);
  EXPECT_NEAR(g05->phase1_cycles, 130418582.443, 1e-6);  // GPS L1C has no phase shift (header)
  EXPECT_TRUE(r.notes.empty());
}

TEST(SignalSelection, Zim2WithoutBiasFileReportsTheConvention) {
  PPP_REQUIRE_SHARED_DATA();
  auto reader = RinexObsReader::open(test::dataPath(kZim2Obs));
  ObsEpoch epoch;
  ASSERT_TRUE(reader.next(epoch));
  const auto r = selectDualFrequency(epoch, reader.header(), {}, nullptr);
  ASSERT_FALSE(r.observations.empty());
  for (const auto& o : r.observations) {
    EXPECT_FALSE(o.code1_osb_m.has_value());
    EXPECT_DOUBLE_EQ(o.code1_m, *epoch.find(o.satellite, o.code1)->value);
  }
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("P1-C1"), std::string::npos) << r.notes[0];
  EXPECT_NE(r.notes[0].find("G05"), std::string::npos) << r.notes[0];
}

TEST(SignalSelection, Ccj2GpsAndGalileoWithWumOsb) {
  PPP_REQUIRE_SHARED_DATA();
  auto reader = RinexObsReader::open(test::dataPath(kCcj2Obs));
  const BiasSinexFile bias_file = readBiasSinexFile(test::dataPath(kCcj2Bia));
  const SinexBiasProvider bias(bias_file, kCcj2Bia);
  ObsEpoch epoch;
  ASSERT_TRUE(reader.next(epoch));
  SignalSelectionOptions options;
  options.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  SignalSelector selector(reader.header(), options, &bias);
  const auto r = selector.select(epoch);
  int gps = 0, galileo = 0;
  for (const auto& o : r.observations) {
    if (o.satellite.system == GnssSystem::GPS) {
      ++gps;
      // CCJ2 GPS types: C1C C2W C2X C5X ... L1C L2W L2X: C1C, C2W (preferred over C2X), L1C, L2W.
      EXPECT_EQ(o.code1, code("C1C"));
      EXPECT_EQ(o.code2, code("C2W"));
      EXPECT_EQ(o.phase1, code("L1C"));
      EXPECT_EQ(o.phase2, code("L2W"));
    } else {
      ++galileo;
      // CCJ2 Galileo types: C1X C5X L1X L5X: E1 and E5a by the X attribute.
      EXPECT_EQ(o.code1, code("C1X"));
      EXPECT_EQ(o.code2, code("C5X"));
      EXPECT_DOUBLE_EQ(o.frequency2_hz, 1176.45e6);
    }
  }
  EXPECT_GE(gps, 8);
  EXPECT_GE(galileo, 1);
  // WUM0MGXRAP_20212100000_01D_01D_ABS.BIA, lines 111 and 115:
  //  OSB  G050 G05  C1C  2021:210:00000 2021:210:86400 ns  -.723700000000000E+01
  //  OSB  G050 G05  C2W  2021:210:00000 2021:210:86400 ns  -.103458000000000E+02
  const auto* g05 = findObs(r, "G05");
  if (g05 != nullptr) {
    EXPECT_NEAR(*g05->code1_osb_m, ns(-7.237), 1e-9);
    EXPECT_NEAR(*g05->code2_osb_m, ns(-10.3458), 1e-9);
  }
  // Lines 63 and 67: G01 C1C 0.978760000000000E+01, C2W 0.176826000000000E+02 ns.
  const auto* g01 = findObs(r, "G01");
  ASSERT_NE(g01, nullptr);
  EXPECT_NEAR(*g01->code1_osb_m, ns(9.7876), 1e-9);
  EXPECT_NEAR(*g01->code2_osb_m, ns(17.6826), 1e-9);
  EXPECT_NEAR(g01->code1_m, *epoch.find(sat("G01"), code("C1C"))->value - ns(9.7876), 1e-9);
}

// The table's rows (RINEX 3.05 table A2 bands): GPS L1/L2, Galileo E1/E5a,
// BeiDou B1I/B3I; GLONASS (FDMA) and the other systems have none.
TEST(SignalSelection, TableHasOneRowPerSystemWithAnIfPair) {
  std::vector<GnssSystem> systems;
  for (const auto& row : signalTable()) systems.push_back(row.system);
  EXPECT_EQ(systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo, GnssSystem::BeiDou}));
  EXPECT_EQ(signalTableRow(GnssSystem::GLONASS), nullptr);
  EXPECT_EQ(signalTableRow(GnssSystem::QZSS), nullptr);
  EXPECT_EQ(signalTableRow(GnssSystem::BeiDou)->priority.band1, '2');
  EXPECT_EQ(signalTableRow(GnssSystem::BeiDou)->priority.band2, '6');
  EXPECT_EQ(signalTableRow(GnssSystem::Galileo)->priority.band2, '5');
  EXPECT_EQ(automaticSignalSystems(), (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  EXPECT_EQ(signalTableSystemNames(), "GPS, Galileo or BeiDou");
  const SignalSelectionOptions options;
  EXPECT_EQ(options.priorities.find(GnssSystem::GLONASS), nullptr);
  EXPECT_EQ(options.priorities[GnssSystem::GPS].code1_attributes, (std::vector<char>{'W', 'C'}));
  EXPECT_THROW(SignalSelectionOptions().priorities[GnssSystem::SBAS], std::out_of_range);
}

// ESBC (SEPT POLARX5) BeiDou types: C2I C6I C7I L2I L6I L7I: B1I/B3I by the I
// attribute; the GEO C05 has no B3I at ESBC (test_beidou_ephemeris) and is skipped.
TEST(SignalSelection, EsbcBeidouPicksB1iB3i) {
  PPP_REQUIRE_SHARED_DATA();
  RinexObsReader reader(openObservationSource(test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz")));
  ObsEpoch epoch;
  ASSERT_TRUE(reader.next(epoch));
  SignalSelectionOptions options;
  options.systems = {GnssSystem::BeiDou};
  SignalSelector selector(reader.header(), options, nullptr);
  const auto r = selector.select(epoch);
  ASSERT_GE(r.observations.size(), 5u);
  // Carriers: BDS-SIS-ICD-B1I 3.0 (B1I 1561.098 MHz), BDS-SIS-ICD-B3I 1.0 (B3I 1268.52 MHz).
  for (const auto& o : r.observations)
    expectSignals(o, GnssSystem::BeiDou, "C2I", "C6I", "L2I", "L6I", 1561.098e6, 1268.52e6);
  bool c05_skipped = false;
  for (const auto& s : r.skipped)
    if (s.satellite == sat("C05")) c05_skipped = s.reason == "missing code band 2 phase band 2";
  EXPECT_TRUE(c05_skipped);
  EXPECT_TRUE(r.notes.empty());  // no clock-reference note: the row states none for BeiDou
}

TEST(SignalSelection, PriorityIsConfigurable) {
  PPP_REQUIRE_SHARED_DATA();
  auto reader = RinexObsReader::open(test::dataPath(kCcj2Obs));
  ObsEpoch epoch;
  ASSERT_TRUE(reader.next(epoch));
  SignalSelectionOptions options;
  options.priorities[GnssSystem::GPS].code2_attributes = {'X', 'W'};
  options.priorities[GnssSystem::GPS].phase2_attributes = {'X', 'W'};
  const auto r = selectDualFrequency(epoch, reader.header(), options, nullptr);
  ASSERT_FALSE(r.observations.empty());
  for (const auto& o : r.observations) {
    if (epoch.find(o.satellite, code("C2X")) && epoch.find(o.satellite, code("C2X"))->value) {
      EXPECT_EQ(o.code2, code("C2X")) << o.satellite.toString();
      EXPECT_EQ(o.phase2, code("L2X")) << o.satellite.toString();
    } else {
      EXPECT_EQ(o.code2, code("C2W")) << o.satellite.toString();  // fallback for satellites without L2C
    }
  }
}

TEST(SignalSelection, MissingOsbSkipsTheSatelliteWhenRequired) {
  PPP_REQUIRE_SHARED_DATA();
  auto reader = RinexObsReader::open(test::dataPath(kZim2Obs));
  BiasSinexFile bias = readBiasSinexFile(test::dataPath(kZim2Bia));
  // Remove G05's C1C row.
  bias.records.erase(std::remove_if(bias.records.begin(), bias.records.end(),
                                    [](const BiasRecord& b) {
                                      return b.satellite && *b.satellite == sat("G05") && b.obs1 == code("C1C");
                                    }),
                     bias.records.end());
  bias.buildIndex();
  const SinexBiasProvider biases(bias, kZim2Bia);
  ObsEpoch epoch;
  ASSERT_TRUE(reader.next(epoch));
  const auto r = selectDualFrequency(epoch, reader.header(), {}, &biases);
  EXPECT_EQ(findObs(r, "G05"), nullptr);
  bool reason = false;
  for (const auto& s : r.skipped) reason |= s.satellite == sat("G05") && s.reason.find("no OSB") != std::string::npos;
  EXPECT_TRUE(reason);
  SignalSelectionOptions lenient;
  lenient.require_code_osb = false;
  const auto r2 = selectDualFrequency(epoch, reader.header(), lenient, &biases);
  const auto* g05 = findObs(r2, "G05");
  ASSERT_NE(g05, nullptr);
  EXPECT_FALSE(g05->code1_osb_m.has_value());
  EXPECT_TRUE(g05->code2_osb_m.has_value());
}

/// A one-satellite header/epoch built in memory.
struct Synthetic {
  RinexObsHeader header;
  ObsEpoch epoch;
  Synthetic(std::uint8_t lli1, std::uint8_t lli2) {
    header.version = 3.04;
    header.major_version = 3;
    auto& g = header.obs_types[static_cast<int>(GnssSystem::GPS)];
    g = {code("C1C"), code("L1C"), code("C2W"), code("L2W"), code("L2L"), code("S1C")};
    header.phase_shifts.push_back({GnssSystem::GPS, code("L2L"), -0.25, {}});
    epoch.time = test::gpst(2026, 5, 13);
    epoch.satellites.push_back({sat("G07"), 0, 6});
    epoch.observations = {{code("C1C"), 2.2e7, std::nullopt, std::nullopt},
                          {code("L1C"), 1.1e8, lli1, std::nullopt},
                          {code("C2W"), 2.2e7 + 3.0, std::nullopt, std::nullopt},
                          {code("L2W"), std::nullopt, std::nullopt, std::nullopt},  // blank: L2L is used
                          {code("L2L"), 8.6e7, lli2, std::nullopt},
                          {code("S1C"), 45.5, std::nullopt, std::nullopt}};
  }
};

TEST(SignalSelection, LossOfLockBitsAndPhaseShift) {
  // RINEX 3.05 sec. 5.3: LLI bit 0 = loss of lock, bit 1 = half-cycle ambiguity.
  Synthetic s(1, 2);
  auto r = selectDualFrequency(s.epoch, s.header, {}, nullptr);
  ASSERT_EQ(r.observations.size(), 1u);
  const auto& o = r.observations[0];
  EXPECT_TRUE(o.loss_of_lock1);
  EXPECT_FALSE(o.loss_of_lock2);
  EXPECT_TRUE(o.half_cycle_ambiguity);
  EXPECT_EQ(o.phase2, code("L2L"));
  ASSERT_TRUE(o.cn0_1_dbhz.has_value());
  EXPECT_DOUBLE_EQ(*o.cn0_1_dbhz, 45.5);
  // As written (default): the -0.25 cycle of SYS / PHASE SHIFT is already in the value.
  EXPECT_DOUBLE_EQ(o.phase2_cycles, 8.6e7);
  SignalSelectionOptions restore;
  restore.phase_shift = PhaseShiftHandling::RestoreOriginal;
  r = selectDualFrequency(s.epoch, s.header, restore, nullptr);
  EXPECT_DOUBLE_EQ(r.observations[0].phase2_cycles, 8.6e7 + 0.25);  // original = file - shift
  Synthetic t(3, 0);
  r = selectDualFrequency(t.epoch, t.header, {}, nullptr);
  EXPECT_TRUE(r.observations[0].loss_of_lock1);
  EXPECT_TRUE(r.observations[0].half_cycle_ambiguity);
  EXPECT_FALSE(r.observations[0].loss_of_lock2);
}

TEST(SignalSelection, MissingSignalGivesReason) {
  Synthetic s(0, 0);
  s.epoch.observations[2].value.reset();  // no C2W
  const auto r = selectDualFrequency(s.epoch, s.header, {}, nullptr);
  EXPECT_TRUE(r.observations.empty());
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_NE(r.skipped[0].reason.find("code band 2"), std::string::npos) << r.skipped[0].reason;
}

}  // namespace
}  // namespace ppp
