// The satellite antenna model of the products (SP3 "/* PCV:", clock "SYS / PCVS
// APPLIED") against the SINEX codes of the ANTEX's satellite antennas, and the
// pipeline's refusal of PPP-AR when they differ (doc/studies/ar_real_data.md: ESBC GRG
// IGS14 products with IGS20 antennas leave narrow-lane offsets per satellite
// that follow the IGS14 - IGS20 z-PCO differences).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/product_antenna_model.h"
#include "ppp_bayes_tree/ppp/ambiguity/antenna_model_consistency.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "esbc_stream_fixture.h"
#include "ppp_dataset.h"
#include "test_support.h"

namespace ppp {
namespace {

bool hasNote(const std::vector<std::string>& notes, const std::string& text) {
  return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n == text; });
}

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(AntennaModelConsistency, FamilyIsTheNameBeforeTheWeek) {
  EXPECT_EQ(antennaModelFamily("IGS14_2108"), "IGS14");
  EXPECT_EQ(antennaModelFamily("igs14_2108.atx"), "IGS14");
  EXPECT_EQ(antennaModelFamily("IGS20"), "IGS20");
  EXPECT_EQ(antennaModelFamily(""), "");
}

TEST(AntennaModelConsistency, VerdictByFamily) {
  // ZIM2's case: another release of the same frame is consistent.
  const auto same = checkAntennaModelConsistency({"IGS20_2417", "igs20_2417"}, {"IGS20_2423"});
  EXPECT_EQ(same.verdict, AntennaModelConsistency::Consistent);
  EXPECT_EQ(same.text(),
            "satellite antenna model consistent with the products (IGS20: products IGS20_2417, ANTEX IGS20_2423)");
  // ESBC's case.
  const auto esbc = checkAntennaModelConsistency({"IGS14_2108", "igs14_2108"}, {"IGS20_2417"});
  EXPECT_TRUE(esbc.different());
  EXPECT_EQ(esbc.text(), "satellite antenna model differs from the products' (products IGS14_2108, ANTEX IGS20_2417)");
  // An ANTEX set that mixes families differs for some satellites.
  EXPECT_TRUE(checkAntennaModelConsistency({"IGS14_2108"}, {"IGS14_2247", "IGS20_2417"}).different());
  // Products that do not name their model are not judged.
  const auto unknown = checkAntennaModelConsistency({""}, {"IGS20_2417"});
  EXPECT_EQ(unknown.verdict, AntennaModelConsistency::Unknown);
  EXPECT_EQ(unknown.text(), "satellite antenna model not judged (products not stated, ANTEX IGS20_2417)");
}

TEST(AntennaModelConsistency, ProductHeadersNameTheirModel) {
  // Header lines as the IGS and GRG files write them (SP3-d comment, RINEX clock 3.04 label).
  const std::string sp3 = writeFile("pcv.sp3",
                                    "#dP2020  6 25  0  0  0.00000000      96 ORBIT IGS14 HLM  GRG\n"
                                    "/* PCV:IGS14_2108 OL/AL:FES2012  NONE     NN ORB:CoN CLK:CoN\n"
                                    "*  2020  6 25  0  0  0.00000000\n"
                                    "/* PCV:IGS20_2417 after the first epoch: not a header\n");
  EXPECT_EQ(productAntennaModel(sp3), "IGS14_2108");
  const std::string clk = writeFile("pcv.clk",
                                    "     3.04           C                   M                   RINEX VERSION / TYPE\n"
                                    "G GINS   V11.1      igs14_2108.atx                          SYS / PCVS APPLIED\n"
                                    "                                                            END OF HEADER\n");
  EXPECT_EQ(productAntennaModel(clk), "igs14_2108");
  const std::string none = writeFile("nopcv.sp3", "/* no antenna model named here\n*  2020  6 25  0  0  0.0\n");
  EXPECT_EQ(productAntennaModel(none), "");
}

TEST(AntennaModelConsistency, RealProductHeaders) {
  PPP_REQUIRE_SHARED_DATA();
  EXPECT_EQ(productAntennaModel(test::dataPath("esbc-2020-177/GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz")),
            "IGS14_2108");
  EXPECT_EQ(productAntennaModel(test::dataPath("esbc-2020-177/GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz")),
            "igs14_2108");
  const test::PppDataset zim2 = test::zim2Dataset();
  EXPECT_EQ(productAntennaModel(zim2.sp3.front()), "IGS20_2417");
  EXPECT_EQ(productAntennaModel(zim2.clk.front()), "igs20_2417");
  const test::PppDataset ccj2 = test::ccj2Dataset();
  EXPECT_EQ(productAntennaModel(ccj2.sp3.front()), "igs14_2148");
  EXPECT_EQ(productAntennaModel(ccj2.clk.front()), "IGS14_2148");
}

TEST(AntennaModelConsistency, RealEsbcIgs14ProductsWithIgs20AntexRefuseAr) {
  PPP_REQUIRE_SHARED_DATA();
  const PppInputFiles files = test::esbcGrgInputFiles();
  const std::string verdict =
      "satellite antenna model differs from the products' (products IGS14_2108, ANTEX IGS20_2417)";
  {
    const PppConfig config = parsePppConfig("ambiguity_resolution:\n  enabled: true\n", "AR");
    const PppPipeline pipeline(files, config);
    const auto notes = pipeline.notes();
    EXPECT_TRUE(hasNote(notes, "warning: " + verdict));
    EXPECT_TRUE(hasNote(notes, "ambiguity resolution: float (enabled: true): satellite antenna model differs from the "
                               "products' (products IGS14_2108, ANTEX IGS20_2417; "
                               "ambiguity_resolution.allow_antenna_model_mismatch: true to fix anyway)"));
    EXPECT_FALSE(hasNote(notes, "ambiguity resolution: integer-recovery clocks with 66 wide-lane satellite biases in "
                                "the clock header"));
    ASSERT_NE(pipeline.productAssembly(), nullptr);
    EXPECT_EQ(pipeline.productAssembly()->phaseBiases(), nullptr);
  }
  {
    const PppConfig config =
        parsePppConfig("ambiguity_resolution:\n  enabled: true\n  allow_antenna_model_mismatch: true\n", "AR allowed");
    const PppPipeline pipeline(files, config);
    const auto notes = pipeline.notes();
    EXPECT_TRUE(hasNote(notes, "ambiguity resolution: antenna model mismatch allowed (allow_antenna_model_mismatch)"));
    EXPECT_TRUE(hasNote(notes, "ambiguity resolution: integer-recovery clocks with 66 wide-lane satellite biases in "
                               "the clock header"));
    EXPECT_NE(pipeline.productAssembly()->phaseBiases(), nullptr);
  }
  {
    // The default (auto): float, with the antenna reason; the resolver does not run.
    const PppPipeline pipeline(files, parsePppConfig("", "auto"));
    const ArGateVerdict& gate = pipeline.productAssembly()->arGate();
    EXPECT_EQ(gate.mode, AmbiguityResolutionMode::Auto);
    EXPECT_FALSE(gate.fix);
    EXPECT_EQ(gate.reason, ArGateReason::AntennaModelDifferent);
    EXPECT_TRUE(hasNote(pipeline.notes(), "ambiguity resolution: float (enabled: auto): satellite antenna model "
                                          "differs from the products' (products IGS14_2108, ANTEX IGS20_2417)"));
    EXPECT_FALSE(pipeline.config().ambiguity_resolution.enabled);
  }
  {
    // Float: the warning only.
    const PppPipeline pipeline(files, parsePppConfig("ambiguity_resolution:\n  enabled: false\n", "float"));
    const auto notes = pipeline.notes();
    EXPECT_TRUE(hasNote(notes, "warning: " + verdict));
    EXPECT_TRUE(std::none_of(notes.begin(), notes.end(), [](const std::string& n) {
      return n.rfind("ambiguity resolution", 0) == 0;
    }));
  }
}

TEST(AntennaModelConsistency, RealZim2IsConsistent) {
  PPP_REQUIRE_SHARED_DATA();
  const test::PppDataset d = test::zim2Dataset();
  PppInputFiles files;
  files.obs = d.obs;
  files.sp3 = d.sp3;
  files.clk = d.clk;
  files.atx = d.atx;
  const PppPipeline pipeline(files, parsePppConfig("", "ZIM2"));
  EXPECT_TRUE(hasNote(pipeline.notes(), "satellite antenna model consistent with the products (IGS20: products "
                                        "IGS20_2417, ANTEX IGS20_2423)"));
}

}  // namespace
}  // namespace ppp
