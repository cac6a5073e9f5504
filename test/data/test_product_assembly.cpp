// The product assembly (product_assembly.h) on the real product sets: the IGS14
// satellite ANTEX reads cleanly, satellite antennas are taken from the products'
// family whatever the order of the ANTEX files, the systems default to those the
// products and antennas cover, and the PPP-AR gate's verdicts (auto) for ZIM2
// (IGS clocks + CODE biases: float), CCJ2 (WUM clocks + WUM OSBs + IGS14: fixes),
// ESBC (GRG integer-recovery clocks + IGS14: fixes) and streamed products.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "esbc_stream_fixture.h"
#include "ppp_dataset.h"
#include "test_support.h"

namespace ppp {
namespace {

const std::string kIgs14 = "antex/igs14_2178_satellites.atx";
const std::string kIgs20Zim2 = "antex/igs20_zim2_gps_trim.atx";  // receiver file that also holds IGS20 GPS satellites

bool hasNote(const std::vector<std::string>& notes, const std::string& text) {
  return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n == text; });
}

std::size_t notesStartingWith(const std::vector<std::string>& notes, const std::string& prefix) {
  return static_cast<std::size_t>(
      std::count_if(notes.begin(), notes.end(), [&](const std::string& n) { return n.rfind(prefix, 0) == 0; }));
}

/// A dataset's products as the assembly's inputs.
ProductAssemblyInputs assemblyInputs(const test::PppDataset& d) {
  ProductAssemblyInputs in;
  in.sp3 = d.sp3;
  in.clk = d.clk;
  in.atx = d.atx;
  in.bias = d.bia;
  return in;
}

/// CCJ2's WUM products with the given ANTEX files.
ProductAssemblyInputs ccj2Inputs(const std::vector<std::string>& atx) {
  ProductAssemblyInputs in = assemblyInputs(test::ccj2Dataset());
  in.blq = test::dataPath("oceanload/ccj2_fes2004.blq");
  in.atx.clear();
  for (const auto& a : atx) in.atx.push_back(test::dataPath(a));
  return in;
}

TEST(ProductAssembly, RealIgs14AntexReadsWithoutProblems) {
  PPP_REQUIRE_SHARED_DATA();
  const AntexFile file = readAntexFile(test::dataPath(kIgs14));
  EXPECT_TRUE(file.report.clean()) << file.report.summary();
  // The GIOVE test satellites (E51, E52) are outside Galileo's PRN range: skipped, listed once each.
  EXPECT_EQ(file.skipped_satellite_codes, (std::vector<std::string>{"E51", "E52"}));
  EXPECT_GT(file.satelliteCount(), 200u);
  ProductFiles files;
  files.atx = {test::dataPath(kIgs14)};
  const ProductSet set = ProductSet::load(files);
  EXPECT_TRUE(set.problems().empty());
  EXPECT_EQ(notesStartingWith(set.notes(), "ANTEX igs14_2178_satellites.atx:"), 1u);
  EXPECT_TRUE(hasNote(set.notes(), "ANTEX igs14_2178_satellites.atx: satellite blocks outside the systems' PRN "
                                   "ranges skipped: E51 E52"));
}

TEST(ProductAssembly, Ccj2SatelliteAntennasFromTheProductsFamilyInEitherOrder) {
  PPP_REQUIRE_SHARED_DATA();
  for (const auto& order : {std::vector<std::string>{kIgs14, kIgs20Zim2}, std::vector<std::string>{kIgs20Zim2, kIgs14}}) {
    SCOPED_TRACE(order.front());
    const ProductAssembly a = ProductAssembly::assemble(ccj2Inputs(order), PppConfig{});
    EXPECT_TRUE(a.problems().empty()) << a.problems().front();
    EXPECT_EQ(a.antennas()->satelliteFamily(), "IGS14");
    // Every satellite in use (GPS and Galileo of the WUM products) from the IGS14 file.
    EXPECT_EQ(notesStartingWith(a.notes(), "satellite antennas: the products' family IGS14 taken first of 2 ANTEX "
                                           "files ("),
              1u);
    for (const auto& n : a.notes())
      if (n.rfind("satellite antennas:", 0) == 0) {
        EXPECT_NE(n.find(" from igs14_2178_satellites.atx)"), std::string::npos) << n;
        EXPECT_EQ(n.find("igs20_zim2_gps_trim.atx"), std::string::npos) << n;
      }
    EXPECT_TRUE(hasNote(a.notes(), "satellite antenna model consistent with the products (IGS14: products "
                                   "IGS14_2148, ANTEX IGS14_2178)"));
    // The G01 block in use is IGS14's even when the IGS20 file comes first.
    const auto g01 = a.antennas()->satellite(*SatelliteId::parse("G01"), GnssTime::fromCalendar({2021, 7, 29, 0, 0, 0.0}, TimeSystem::GPS));
    ASSERT_NE(g01.calibration, nullptr);
    EXPECT_EQ(g01.source, "igs14_2178_satellites.atx");
    EXPECT_EQ(antennaModelFamily(g01.calibration->sinex_code), "IGS14");
  }
}

TEST(ProductAssembly, Ccj2AutoFixesWithWumOsbsAndIgs14Antennas) {
  PPP_REQUIRE_SHARED_DATA();
  const ProductAssembly a = ProductAssembly::assemble(ccj2Inputs({kIgs14, kIgs20Zim2}), PppConfig{});
  const ArGateVerdict& gate = a.arGate();
  EXPECT_EQ(gate.mode, AmbiguityResolutionMode::Auto);
  EXPECT_TRUE(gate.fix);
  EXPECT_EQ(gate.reason, ArGateReason::Fixing);
  EXPECT_EQ(gate.phase, PhaseInformation::AnalysisCentreOsb);
  // The centres from the headers: the clock file's "PGM / RUN BY" WHU, the Bias-SINEX agency WHU.
  EXPECT_TRUE(hasNote(a.notes(), "ambiguity resolution: phase biases consistent with the clocks (WHU, from the headers)"));
  EXPECT_TRUE(hasNote(a.notes(), "ambiguity resolution: fixing (enabled: auto): phase OSBs of the clocks' analysis "
                                 "centre (WHU, from the headers)"));
  EXPECT_NE(a.phaseBiases(), nullptr);
  EXPECT_EQ(a.phaseBiases(), a.codeBiases().get());  // the Bias-SINEX file serves both
  EXPECT_TRUE(a.config().ambiguity_resolution.enabled);
  // WUM carries GPS, GLONASS and Galileo, the IGS14 file has all three: all are processed
  // (BeiDou, which WUM carries too, only when listed).
  EXPECT_EQ(a.config().signals.systems,
            (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo}));
  EXPECT_TRUE(hasNote(a.notes(), "systems: GPS, GLONASS, Galileo (every system of GPS, GLONASS, Galileo that the "
                                 "products and the satellite antennas cover)"));
  // An explicit list is kept as written.
  const PppConfig gps_only = parsePppConfig("measurement_model:\n  signals:\n    systems: [GPS]\n", "gps");
  EXPECT_EQ(ProductAssembly::assemble(ccj2Inputs({kIgs14}), gps_only).config().signals.systems,
            std::vector<GnssSystem>{GnssSystem::GPS});
}

TEST(ProductAssembly, Zim2StaysFloatWithoutConsistentPhaseBiases) {
  PPP_REQUIRE_SHARED_DATA();
  const ProductAssembly a = ProductAssembly::assemble(assemblyInputs(test::zim2Dataset()), PppConfig{});
  const ArGateVerdict& gate = a.arGate();
  EXPECT_FALSE(gate.fix);
  EXPECT_EQ(gate.reason, ArGateReason::NoConsistentPhaseBiases);
  EXPECT_EQ(toString(gate.reason), "no consistent phase biases");
  // IGS combined clocks ("ANALYSIS CENTER" IGS) with CODE's biases (agency COD).
  EXPECT_EQ(gate.text(), "ambiguity resolution: float (enabled: auto): no consistent phase biases (clocks IGS, biases COD)");
  EXPECT_TRUE(hasNote(a.notes(), gate.text()));
  EXPECT_EQ(a.phaseBiases(), nullptr);
  EXPECT_FALSE(a.config().ambiguity_resolution.enabled);  // the float run is the one before `auto`
  // GPS-only products: GLONASS and Galileo are skipped with the reason.
  EXPECT_EQ(a.config().signals.systems, std::vector<GnssSystem>{GnssSystem::GPS});
  EXPECT_TRUE(hasNote(a.notes(), "systems: GLONASS skipped: no orbits and clocks in the products"));
  EXPECT_TRUE(hasNote(a.notes(), "systems: Galileo skipped: no orbits and clocks in the products"));
}

TEST(ProductAssembly, AutoTakesGlonassOnlyWithItsFrequencyChannels) {
  PPP_REQUIRE_SHARED_DATA();
  // ppp_solve hands the observation header's channels: CCJ2's RINEX header has GLONASS SLOT / FRQ #.
  ProductAssemblyInputs in = ccj2Inputs({kIgs14});
  in.observation_glonass_channels = RinexObsReader::open(test::ccj2Dataset().obs).header().glonass_channels;
  ASSERT_GT(in.observation_glonass_channels->size(), 0);
  EXPECT_EQ(ProductAssembly::assemble(in, PppConfig{}).config().signals.systems,
            (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo}));
  // A header without them and precise products (no navigation records): GLONASS cannot be selected.
  in.observation_glonass_channels = GlonassChannels{};
  const ProductAssembly none = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_EQ(none.config().signals.systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  EXPECT_TRUE(hasNote(none.notes(), "systems: GLONASS skipped: no frequency channels (no GLONASS SLOT / FRQ # in "
                                    "the observation header, no navigation records)"));
  // Listed, it is processed as configured (its satellites are then skipped per epoch with the reason).
  const PppConfig listed = parsePppConfig("measurement_model:\n  signals:\n    systems: [G, E, R]\n", "listed");
  EXPECT_EQ(ProductAssembly::assemble(in, listed).config().signals.systems,
            (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo, GnssSystem::GLONASS}));
}

TEST(ProductAssembly, BroadcastCoverageComesFromTheRecordsOfEachSystem) {
  PPP_REQUIRE_SHARED_DATA();
  // The ESBC navigation file holds GPS, Galileo and BeiDou records, no GLONASS ones:
  // auto takes GPS and Galileo (BeiDou only when listed), GLONASS is skipped with the reason.
  ProductAssemblyInputs in;
  in.nav = {test::esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx")};
  in.atx = {test::dataPath(kIgs14), test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
  in.observation_glonass_channels =
      RinexObsReader::open(test::esbcPath("ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz")).header().glonass_channels;
  ASSERT_GT(in.observation_glonass_channels->size(), 0);  // the channels are not what is missing
  const ProductAssembly a = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_EQ(a.config().signals.systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  EXPECT_TRUE(hasNote(a.notes(), "systems: GLONASS skipped: no navigation records"));
}

TEST(ProductAssembly, EsbcIntegerRecoveryClocksFixWithIgs14Antennas) {
  PPP_REQUIRE_SHARED_DATA();
  ProductAssemblyInputs in;
  in.sp3 = {test::dataPath("esbc-2020-177/GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz")};
  in.clk = {test::dataPath("esbc-2020-177/GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz")};
  in.atx = {test::dataPath(kIgs14), test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
  const ProductAssembly a = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_TRUE(a.problems().empty()) << a.problems().front();
  const ArGateVerdict& gate = a.arGate();
  EXPECT_TRUE(gate.fix) << gate.text();
  EXPECT_EQ(gate.phase, PhaseInformation::IntegerRecoveryClocks);
  EXPECT_TRUE(hasNote(a.notes(), "ambiguity resolution: integer-recovery clocks with 66 wide-lane satellite biases in "
                                 "the clock header"));
  EXPECT_NE(a.phaseBiases(), nullptr);
  EXPECT_TRUE(hasNote(a.notes(), "satellite antenna model consistent with the products (IGS14: products IGS14_2108, "
                                 "ANTEX IGS14_2178)"));
  // GRG carries GPS, GLONASS and Galileo; the IGS14 file calibrates all three.
  EXPECT_EQ(a.config().signals.systems,
            (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo}));
  // Off: no verdict note, no phase biases.
  const ProductAssembly off =
      ProductAssembly::assemble(in, parsePppConfig("ambiguity_resolution:\n  enabled: false\n", "off"));
  EXPECT_EQ(off.arGate().reason, ArGateReason::Disabled);
  EXPECT_EQ(off.phaseBiases(), nullptr);
  EXPECT_FALSE(off.config().ambiguity_resolution.enabled);
}

TEST(ProductAssembly, StreamedProductsGoThroughTheSameGate) {
  PPP_REQUIRE_SHARED_DATA();
  // The node's inputs: the same ANTEX and bias files, orbits and clocks from a topic.
  ProductAssemblyInputs streamed = ccj2Inputs({kIgs20Zim2, kIgs14});
  streamed.sp3.clear();
  streamed.clk.clear();
  {
    // Nothing declared about the stream: its antenna model is not known -> auto stays float
    // (the resolver runs, without phase biases it leaves the float as it is).
    ProductAssembly a = ProductAssembly::assemble(streamed, PppConfig{});
    EXPECT_FALSE(a.arGate().fix);
    EXPECT_EQ(a.arGate().reason, ArGateReason::AntennaModelUnknown);
    EXPECT_EQ(a.ephemeris(), nullptr);
    EXPECT_EQ(a.phaseBiases(), nullptr);
    EXPECT_TRUE(a.config().ambiguity_resolution.enabled);
    EXPECT_EQ(a.antennas()->satelliteFamily(), "");
    // The stream declares WUM's clocks and model (e.g. with its first message): decided again.
    StreamedProductInfo wum;
    wum.clock_centre = "WHU";
    wum.antenna_model = "IGS14_2148";
    EXPECT_TRUE(a.declareStreamedProducts(wum));
    EXPECT_TRUE(a.arGate().fix) << a.arGate().text();
    EXPECT_EQ(a.arGate().phase, PhaseInformation::AnalysisCentreOsb);
    EXPECT_EQ(a.antennas()->satelliteFamily(), "IGS14");
    EXPECT_EQ(a.phaseBiases(), a.codeBiases().get());
    EXPECT_FALSE(a.declareStreamedProducts(wum));  // nothing new
  }
  // Declared like the WUM files: the same verdict and the same biases as from the files.
  streamed.streamed.clock_centre = "WHU";
  streamed.streamed.antenna_model = "IGS14_2148";
  const ProductAssembly node = ProductAssembly::assemble(streamed, PppConfig{});
  const ProductAssembly files = ProductAssembly::assemble(ccj2Inputs({kIgs20Zim2, kIgs14}), PppConfig{});
  EXPECT_TRUE(node.arGate().fix) << node.arGate().text();
  EXPECT_EQ(node.arGate().phase, files.arGate().phase);
  EXPECT_EQ(node.antennas()->satelliteFamily(), files.antennas()->satelliteFamily());
  EXPECT_EQ(node.config().signals.systems, files.config().signals.systems);
  EXPECT_EQ(node.config().ambiguity_resolution.enabled, files.config().ambiguity_resolution.enabled);
  // Streamed SSR phase biases do not replace a consistent Bias-SINEX file.
  ProductAssembly node_ssr = ProductAssembly::assemble(streamed, PppConfig{});
  EXPECT_FALSE(node_ssr.acceptStreamedPhaseBiases(files.codeBiases().get(), PhaseInformation::SsrPhaseBiases));
  EXPECT_EQ(node_ssr.phaseBiases(), node_ssr.codeBiases().get());
  // Without the bias file, the stream's phase biases are taken when they arrive.
  streamed.bias.reset();
  ProductAssembly live = ProductAssembly::assemble(streamed, PppConfig{});
  EXPECT_FALSE(live.arGate().fix);
  EXPECT_EQ(live.arGate().reason, ArGateReason::NoConsistentPhaseBiases);
  EXPECT_TRUE(live.config().ambiguity_resolution.enabled);  // the resolver waits for them
  EXPECT_TRUE(live.acceptStreamedPhaseBiases(files.codeBiases().get(), PhaseInformation::SsrPhaseBiases));
  EXPECT_TRUE(live.arGate().fix);
  EXPECT_EQ(live.phaseBiases(), files.codeBiases().get());
  EXPECT_FALSE(live.acceptStreamedPhaseBiases(files.codeBiases().get(), PhaseInformation::SsrPhaseBiases));
}

/// The notes that contain `text`.
std::size_t notesContaining(const std::vector<std::string>& notes, const std::string& text) {
  return static_cast<std::size_t>(
      std::count_if(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(text) != std::string::npos; }));
}

TEST(ProductAssembly, StreamDeclarationReplacesTheEarlierDecisionAndKeepsTheConfiguredMode) {
  PPP_REQUIRE_SHARED_DATA();
  ProductAssemblyInputs streamed = ccj2Inputs({kIgs20Zim2, kIgs14});
  streamed.sp3.clear();
  streamed.clk.clear();
  ProductAssembly a = ProductAssembly::assemble(streamed, PppConfig{});  // enabled: auto
  EXPECT_EQ(notesContaining(a.notes(), "the products name no satellite antenna model"), 1u);
  StreamedProductInfo wum;
  wum.clock_centre = "WHU";
  wum.antenna_model = "IGS14_2148";
  ASSERT_TRUE(a.declareStreamedProducts(wum));
  // One decision in the notes, the declared one; the mode as configured.
  EXPECT_EQ(a.arGate().mode, AmbiguityResolutionMode::Auto);
  EXPECT_EQ(notesContaining(a.notes(), "the products name no satellite antenna model"), 0u);
  EXPECT_EQ(notesContaining(a.notes(), "(enabled: true)"), 0u);
  EXPECT_EQ(notesStartingWith(a.notes(), "ambiguity resolution: fixing (enabled: auto)"), 1u);
  EXPECT_EQ(notesStartingWith(a.notes(), "ambiguity resolution: float"), 0u);
  EXPECT_TRUE(hasNote(a.notes(), "the product stream declares clocks of WHU and the satellite antenna model IGS14_2148"));
  EXPECT_EQ(notesStartingWith(a.notes(), "satellite antenna model consistent with the products (IGS14"), 1u);

  // A stream that names its clocks but no antenna model: auto stays float, as
  // before the declaration (the model is still not known).
  ProductAssembly b = ProductAssembly::assemble(streamed, PppConfig{});
  StreamedProductInfo clocks_only;
  clocks_only.clock_centre = "WHU";
  ASSERT_TRUE(b.declareStreamedProducts(clocks_only));
  EXPECT_EQ(b.arGate().mode, AmbiguityResolutionMode::Auto);
  EXPECT_FALSE(b.arGate().fix) << b.arGate().text();
  EXPECT_EQ(b.arGate().reason, ArGateReason::AntennaModelUnknown);
  EXPECT_EQ(notesContaining(b.notes(), "satellite antenna model consistent"), 0u);
}

TEST(ProductAssembly, LiveSsrFeedTakesItsAntennaModelFromTheConfigurationAndSaysWhenItIsNotSet) {
  PPP_REQUIRE_SHARED_DATA();
  // The node on a live SSR feed (ros.live corrections): streamed orbits and clocks, no
  // Bias-SINEX, IGS20 satellite antennas. RTCM SSR names no antenna model.
  ProductAssemblyInputs live;
  live.atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx")};
  live.live_ssr = true;
  const ProductAssembly unset = ProductAssembly::assemble(live, PppConfig{});  // ppp.yaml: ""
  // Only GPS satellites in the ANTEX file: Galileo skipped.
  EXPECT_EQ(unset.config().signals.systems, std::vector<GnssSystem>{GnssSystem::GPS});
  EXPECT_TRUE(hasNote(unset.notes(), "systems: Galileo skipped: no satellite antenna calibrations in the ANTEX files"));
  // Which systems a live feed corrects shows only as it streams: auto leaves GLONASS out.
  live.atx.push_back(test::dataPath(kIgs14));
  const ProductAssembly with_glonass_antennas = ProductAssembly::assemble(live, PppConfig{});
  EXPECT_EQ(with_glonass_antennas.config().signals.systems,
            (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  EXPECT_TRUE(hasNote(with_glonass_antennas.notes(),
                      "systems: GLONASS skipped: a live SSR feed shows which systems it corrects only as it streams, "
                      "after the receiver state is made; list it in signals.systems to process it"));
  live.live_ssr = false;  // a PreciseCorrections stream (bag, topic): GLONASS taken as from the precise files
  EXPECT_EQ(ProductAssembly::assemble(live, PppConfig{}).config().signals.systems,
            (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo}));
  live.live_ssr = true;
  live.atx.pop_back();
  EXPECT_FALSE(unset.arGate().fix);
  EXPECT_EQ(unset.arGate().reason, ArGateReason::AntennaModelUnknown);
  EXPECT_EQ(unset.arGate().text(),
            "ambiguity resolution: float (enabled: auto): satellite antenna model of the products not known (SSR "
            "streams name no satellite antenna model: set ssr.antenna_model to the provider's (IGS20 for the IGS "
            "real-time service's streams))");
  // config/live.yaml's IGS20 with IGS20 antennas: the gate waits for the feed's phase biases, then fixes.
  const std::string repo = PPP_REPO_DIR;
  const PppConfig live_yaml = loadPppConfig(std::vector<std::string>{repo + "/config/ppp.yaml", repo + "/config/live.yaml"});
  ASSERT_EQ(live_yaml.ssr.antenna_model, "IGS20");
  ProductAssembly igs20 = ProductAssembly::assemble(live, live_yaml);
  EXPECT_EQ(igs20.arGate().reason, ArGateReason::NoConsistentPhaseBiases) << igs20.arGate().text();
  EXPECT_EQ(igs20.arGate().detail, "no phase biases from the stream yet");
  EXPECT_EQ(igs20.antennas()->satelliteFamily(), "IGS20");
  ProductAssembly reference = ProductAssembly::assemble(ccj2Inputs({kIgs14}), PppConfig{});
  EXPECT_TRUE(igs20.acceptStreamedPhaseBiases(reference.codeBiases().get(), PhaseInformation::SsrPhaseBiases));
  EXPECT_TRUE(igs20.arGate().fix);
  // A model the antennas do not match: float, with that reason.
  const ProductAssembly igs14 =
      ProductAssembly::assemble(live, parsePppConfig("ssr:\n  antenna_model: IGS14\n", "igs14 stream"));
  EXPECT_EQ(igs14.arGate().reason, ArGateReason::AntennaModelDifferent);
  // Without live_ssr (a bag's stream, which declares its model itself) the configuration is not taken.
  live.live_ssr = false;
  EXPECT_EQ(ProductAssembly::assemble(live, live_yaml).arGate().detail, "the products name no satellite antenna model");
}

TEST(ProductAssembly, BroadcastAndSsrFilesGoThroughTheSameGate) {
  PPP_REQUIRE_SHARED_DATA();
  // ppp_solve --nav --ssr: IGS's SSRA03IGS0 recording carries code biases, no phase biases (1059/1242/1260 only).
  ProductAssemblyInputs in;
  in.nav = {test::dataPath("streams/ssr/BRDC00WRD_S_20261880000_01D_MN_GPS_SSR_20261881400.rnx")};
  in.ssr = test::dataPath("streams/ssr/SSRA03IGS0_2026188140760_3epoch.rtcm3");
  in.stream_reference_time = GnssTime::fromCalendar({2026, 7, 7, 14, 0, 0.0}, TimeSystem::GPS);
  in.atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx")};
  const ProductAssembly automatic = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_NE(automatic.ephemeris(), nullptr);
  ASSERT_NE(automatic.codeBiases(), nullptr);
  EXPECT_NE(automatic.codeBiases()->describeSource().find("SSR"), std::string::npos);
  // The SSR stream names no satellite antenna model: auto stays float.
  EXPECT_EQ(automatic.arGate().reason, ArGateReason::AntennaModelUnknown);
  EXPECT_EQ(automatic.phaseBiases(), nullptr);
  // The navigation file holds GPS records only: Galileo and GLONASS skipped for that
  // (before the ANTEX file, which holds GPS satellites only, is looked at).
  EXPECT_EQ(automatic.config().signals.systems, std::vector<GnssSystem>{GnssSystem::GPS});
  EXPECT_TRUE(hasNote(automatic.notes(), "systems: Galileo skipped: no navigation records"));
  EXPECT_TRUE(hasNote(automatic.notes(), "systems: GLONASS skipped: no navigation records"));
  // true: the antennas are not held against it, but there are no phase biases.
  const ProductAssembly on =
      ProductAssembly::assemble(in, parsePppConfig("ambiguity_resolution:\n  enabled: true\n", "on"));
  EXPECT_EQ(on.arGate().reason, ArGateReason::NoConsistentPhaseBiases);
  EXPECT_EQ(on.arGate().detail, "the SSR stream carries no phase biases");
  EXPECT_TRUE(on.config().ambiguity_resolution.enabled);
}

TEST(ProductAssembly, SsrPhaseBiasesFixWhenTheStreamsAntennaModelIsStated) {
  PPP_REQUIRE_SHARED_DATA();
  // ppp_solve --nav --ssr on a stream ppp_ssr_encode made from the GRG products with
  // the phase biases of their integer-recovery clocks (one hour, GPS and Galileo).
  const std::string clk = test::esbcPath("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz");
  std::vector<std::string> problems;
  const auto wide_lane = integerRecoveryClockBiases({readRinexClockHeader(clk)}, {clk}, problems);
  ASSERT_NE(wide_lane, nullptr);
  ProductAssemblyInputs in;
  in.nav = {test::esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx")};
  const GnssTime start = test::gpst(2020, 6, 25, 1, 0, 0);
  SsrFromPreciseOptions options;
  options.systems = {GnssSystem::GPS, GnssSystem::Galileo};
  const auto dir = test::tempDir("assembly_ssr_phase");
  in.ssr = (dir / "SSRC00TST_esbc.rtcm3").string();
  test::writeFileBytes(*in.ssr, test::ssrStreamBytes(ssrFromPrecise({readRinexNav(in.nav.front())}, test::esbcGrgPrecise(),
                                                                     nullptr, wide_lane.get(), start, start + 600.0,
                                                                     options, wide_lane.get())));
  in.atx = {test::dataPath(kIgs14), test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
  // RTCM SSR names no antenna model: auto stays float until the configuration states it.
  const ProductAssembly unknown = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_EQ(unknown.arGate().reason, ArGateReason::AntennaModelUnknown);
  EXPECT_EQ(unknown.phaseBiases(), nullptr);
  const ProductAssembly igs14 = ProductAssembly::assemble(in, parsePppConfig("ssr:\n  antenna_model: IGS14\n", "igs14"));
  EXPECT_EQ(igs14.arGate().reason, ArGateReason::Fixing);
  EXPECT_EQ(igs14.arGate().phase, PhaseInformation::SsrPhaseBiases);
  ASSERT_NE(igs14.phaseBiases(), nullptr);
  EXPECT_EQ(igs14.phaseBiases(), igs14.codeBiases().get());
  EXPECT_EQ(igs14.config().signals.systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  EXPECT_TRUE(hasNote(igs14.notes(), "systems: GLONASS skipped: no navigation records"));
  EXPECT_TRUE(igs14.config().ambiguity_resolution.enabled);
  // A model other than the ANTEX satellites' refuses.
  const ProductAssembly igs20 = ProductAssembly::assemble(in, parsePppConfig("ssr:\n  antenna_model: IGS20\n", "igs20"));
  EXPECT_EQ(igs20.arGate().reason, ArGateReason::AntennaModelDifferent);
  EXPECT_EQ(igs20.phaseBiases(), nullptr);
  // A stream that corrects GPS only: Galileo, whose records the navigation file holds, is skipped.
  options.systems = {GnssSystem::GPS};
  test::writeFileBytes(*in.ssr, test::ssrStreamBytes(ssrFromPrecise({readRinexNav(in.nav.front())}, test::esbcGrgPrecise(),
                                                                     nullptr, nullptr, start, start + 60.0, options)));
  const ProductAssembly gps = ProductAssembly::assemble(in, PppConfig{});
  EXPECT_EQ(gps.config().signals.systems, std::vector<GnssSystem>{GnssSystem::GPS});
  EXPECT_TRUE(hasNote(gps.notes(), "systems: Galileo skipped: no SSR orbit and clock corrections in the stream"));
  std::filesystem::remove_all(dir);
}

TEST(ProductAssembly, PppSolvePipelineUsesTheAssembly) {
  PPP_REQUIRE_SHARED_DATA();
  const PppPipeline pipeline(test::inputFiles(test::zim2Dataset()), PppConfig{});
  ASSERT_NE(pipeline.productAssembly(), nullptr);
  EXPECT_EQ(pipeline.productAssembly()->arGate().reason, ArGateReason::NoConsistentPhaseBiases);
  EXPECT_EQ(pipeline.config().signals.systems, std::vector<GnssSystem>{GnssSystem::GPS});
  EXPECT_TRUE(hasNote(pipeline.notes(), pipeline.productAssembly()->arGate().text()));
}

}  // namespace
}  // namespace ppp
