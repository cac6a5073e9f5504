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
  EXPECT_NE(r.notes[0].describe().find("P1-C1"), std::string::npos) << r.notes[0].describe();
  EXPECT_NE(r.notes[0].describe().find("G05"), std::string::npos) << r.notes[0].describe();
}

/// The first CCJ2 epoch through a selector of `systems` with WUM's OSBs (`epoch`: that epoch).
SignalSelectionResult selectFirstCcj2Epoch(const std::vector<GnssSystem>& systems, ObsEpoch& epoch,
                                           RinexObsHeader* header = nullptr) {
  auto reader = RinexObsReader::open(test::dataPath(kCcj2Obs));
  const BiasSinexFile bias_file = readBiasSinexFile(test::dataPath(kCcj2Bia));
  const SinexBiasProvider bias(bias_file, kCcj2Bia);
  EXPECT_TRUE(reader.next(epoch));
  SignalSelectionOptions options;
  options.systems = systems;
  SignalSelector selector(reader.header(), options, &bias);
  if (header != nullptr) *header = reader.header();
  return selector.select(epoch);
}

TEST(SignalSelection, Ccj2GpsAndGalileoWithWumOsb) {
  PPP_REQUIRE_SHARED_DATA();
  ObsEpoch epoch;
  const auto r = selectFirstCcj2Epoch({GnssSystem::GPS, GnssSystem::Galileo}, epoch);
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

// The table's rows (RINEX 3.05 table A2 bands): GPS L1/L2, GLONASS G1/G2 (FDMA),
// Galileo E1/E5a, BeiDou B1I/B3I; the other systems have none.
TEST(SignalSelection, TableHasOneRowPerSystemWithAnIfPair) {
  std::vector<GnssSystem> systems;
  for (const auto& row : signalTable()) systems.push_back(row.system);
  EXPECT_EQ(systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo,
                                              GnssSystem::BeiDou}));
  EXPECT_EQ(signalTableRow(GnssSystem::QZSS), nullptr);
  EXPECT_EQ(signalTableRow(GnssSystem::BeiDou)->priority.band1, '2');
  EXPECT_EQ(signalTableRow(GnssSystem::BeiDou)->priority.band2, '6');
  EXPECT_EQ(signalTableRow(GnssSystem::Galileo)->priority.band2, '5');
  EXPECT_EQ(automaticSignalSystems(),
            (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo}));
  EXPECT_EQ(signalTableSystemNames(), "GPS, GLONASS, Galileo or BeiDou");
  const SignalSelectionOptions options;
  EXPECT_EQ(options.priorities[GnssSystem::GPS].code1_attributes, (std::vector<char>{'W', 'C'}));
  EXPECT_THROW(SignalSelectionOptions().priorities[GnssSystem::SBAS], std::out_of_range);
}

// GLONASS: G1/G2 with the P codes first (the C1P/C2P clock reference), FDMA, its
// code down-weighted, taken by `auto` where the products cover it; the only row
// whose ambiguities are never fixed.
TEST(SignalSelection, GlonassRowIsFdmaWithPCodesFirst) {
  const SignalTableRow* row = signalTableRow(GnssSystem::GLONASS);
  ASSERT_NE(row, nullptr);
  EXPECT_STREQ(row->config_key, "glonass");
  EXPECT_TRUE(row->frequency_division);
  EXPECT_TRUE(row->automatic);
  EXPECT_EQ(row->priority.band1, '1');
  EXPECT_EQ(row->priority.band2, '2');
  EXPECT_EQ(row->priority.code1_attributes, (std::vector<char>{'P', 'C'}));
  EXPECT_EQ(row->priority.phase2_attributes, (std::vector<char>{'P', 'C'}));
  EXPECT_EQ(row->clock_reference1, 'P');
  EXPECT_EQ(row->clock_reference2, 'P');
  EXPECT_GT(row->priority.code_sigma_factor, 1.0);
  EXPECT_FALSE(integerAmbiguitySystem(GnssSystem::GLONASS));
  EXPECT_TRUE(integerAmbiguitySystem(GnssSystem::GPS));
  EXPECT_TRUE(integerAmbiguitySystem(GnssSystem::Galileo));
  EXPECT_TRUE(integerAmbiguitySystem(GnssSystem::BeiDou));
  EXPECT_FALSE(integerAmbiguitySystem(GnssSystem::QZSS));  // no row: not processed at all
}

/// A GLONASS header/epoch in memory: R01 on channel k = 1, R02 on k = -4, R03 without a channel.
struct SyntheticGlonass {
  RinexObsHeader header;
  ObsEpoch epoch;
  SyntheticGlonass() {
    header.version = 3.04;
    header.major_version = 3;
    header.obs_types[static_cast<int>(GnssSystem::GLONASS)] = {code("C1C"), code("C1P"), code("L1C"), code("L1P"),
                                                               code("C2C"), code("C2P"), code("L2C"), code("L2P")};
    header.glonass_channels.set(1, 1);
    header.glonass_channels.set(2, -4);
    epoch.time = test::gpst(2021, 7, 29);
    for (const char* s : {"R01", "R02", "R03"}) {
      epoch.satellites.push_back({sat(s), static_cast<std::uint32_t>(epoch.observations.size()), 8});
      for (const char* c : {"C1C", "C1P", "L1C", "L1P", "C2C", "C2P", "L2C", "L2P"})
        epoch.observations.push_back({code(c), c[0] == 'C' ? 2.1e7 : 1.1e8, std::nullopt, std::nullopt});
    }
  }
};

// GLONASS ICD 5.1 (2008), sec. 3.3.1.4, table 3.10/3.11: G1 = 1602 + 0.5625 k MHz,
// G2 = 1246 + 0.4375 k MHz; k = 1: 1602.5625 / 1246.4375 MHz; k = -4: 1599.75 / 1244.25 MHz.
TEST(SignalSelection, GlonassFrequenciesPerSatelliteFromTheChannel) {
  SyntheticGlonass s;
  SignalSelectionOptions options;
  options.systems = {GnssSystem::GLONASS};
  const auto r = selectDualFrequency(s.epoch, s.header, options, nullptr);
  ASSERT_EQ(r.observations.size(), 2u);
  expectSignals(r.observations[0], GnssSystem::GLONASS, "C1P", "C2P", "L1P", "L2P", 1602.5625e6, 1246.4375e6);
  expectSignals(r.observations[1], GnssSystem::GLONASS, "C1P", "C2P", "L1P", "L2P", 1599.75e6, 1244.25e6);
  EXPECT_DOUBLE_EQ(r.observations[0].code_sigma_factor, signalTableRow(GnssSystem::GLONASS)->priority.code_sigma_factor);
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_EQ(r.skipped[0].satellite, sat("R03"));
  EXPECT_NE(r.skipped[0].reason.find("no GLONASS frequency channel"), std::string::npos) << r.skipped[0].reason;
  EXPECT_TRUE(r.notes.empty());  // the C1P/C2P clock reference is used
  // A channel known from elsewhere (navigation records): R03 on k = 5; the header's come first.
  options.glonass_channels.set(3, 5);
  options.glonass_channels.set(1, 6);
  const auto r2 = selectDualFrequency(s.epoch, s.header, options, nullptr);
  ASSERT_EQ(r2.observations.size(), 3u);
  EXPECT_DOUBLE_EQ(r2.observations[0].frequency1_hz, 1602.5625e6);
  EXPECT_DOUBLE_EQ(r2.observations[2].frequency1_hz, 1602.0e6 + 5 * 0.5625e6);
  EXPECT_DOUBLE_EQ(r2.observations[2].frequency2_hz, 1246.0e6 + 5 * 0.4375e6);
  // C codes by configuration: the C1P/C2P clock reference note, with the satellites.
  options.priorities[GnssSystem::GLONASS].code1_attributes = {'C'};
  const auto r3 = selectDualFrequency(s.epoch, s.header, options, nullptr);
  ASSERT_EQ(r3.notes.size(), 1u);
  EXPECT_NE(r3.notes[0].describe().find("codes other than C1P/C2P"), std::string::npos) << r3.notes[0].describe();
  EXPECT_NE(r3.notes[0].describe().find("R01 R02 R03"), std::string::npos) << r3.notes[0].describe();
}

// CCJ2 (TRIMBLE NETR9) GLONASS: C1C C1P C2C C2P L1C L1P L2C L2P with every
// channel in GLONASS SLOT / FRQ # (R01 1, R02 -4, R05 1, R21 4, ...); WUM's OSBs
// for the P codes (WUM0MGXRAP_20212100000_01D_01D_ABS.BIA: R05 C1P -.124340E+01,
// C2P -.205540E+01 ns).
TEST(SignalSelection, Ccj2GlonassWithWumOsb) {
  PPP_REQUIRE_SHARED_DATA();
  ObsEpoch epoch;
  RinexObsHeader header;
  const auto r = selectFirstCcj2Epoch({GnssSystem::GLONASS}, epoch, &header);
  EXPECT_EQ(header.glonass_channels.channel(5), 1);
  EXPECT_GE(r.observations.size(), 4u);
  const auto* r05 = findObs(r, "R05");
  ASSERT_NE(r05, nullptr);
  expectSignals(*r05, GnssSystem::GLONASS, "C1P", "C2P", "L1P", "L2P", 1602.5625e6, 1246.4375e6);
  EXPECT_NEAR(*r05->code1_osb_m, ns(-1.2434), 1e-9);
  EXPECT_NEAR(*r05->code2_osb_m, ns(-2.0554), 1e-9);
  const auto* r21 = findObs(r, "R21");  // channel 4
  ASSERT_NE(r21, nullptr);
  EXPECT_DOUBLE_EQ(r21->frequency1_hz, 1604.25e6);
  EXPECT_DOUBLE_EQ(r21->frequency2_hz, 1247.75e6);
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
