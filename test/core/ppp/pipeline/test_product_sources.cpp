// The table of orbit and clock sources (ppp/pipeline/product_sources.h): which
// inputs select which row, what a combination of no row is told, and that the
// product assembly goes through the table.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/ppp/pipeline/product_sources.h"

namespace ppp {
namespace {

TEST(ProductSources, EachCombinationOfInputsSelectsOneRow) {
  std::set<unsigned> inputs;
  std::set<std::string_view> names;
  for (const ProductSource& s : kProductSources) {
    EXPECT_TRUE(inputs.insert(s.inputs).second) << s.name << ": its inputs select another row already";
    EXPECT_TRUE(names.insert(s.name).second) << s.name;
    EXPECT_NE(s.load, nullptr) << s.name;
    EXPECT_FALSE(s.description.empty()) << s.name;
  }
  EXPECT_EQ(findProductSource(kProductSp3 | kProductClk)->name, "precise");
  EXPECT_EQ(findProductSource(kProductNav)->name, "broadcast");
  EXPECT_EQ(findProductSource(kProductNav | kProductSsr)->name, "broadcast+ssr");
  EXPECT_EQ(findProductSource(kProductLiveSsr)->name, "live-ssr");
  EXPECT_EQ(findProductSource(0u)->name, "streamed");
}

TEST(ProductSources, TheRowsSayWhatTheirSourcesAre) {
  // SSR sources name no satellite antenna model: the configuration's ssr.antenna_model is theirs.
  EXPECT_TRUE(findProductSource(kProductNav | kProductSsr)->ssr_antenna_model);
  EXPECT_TRUE(findProductSource(kProductLiveSsr)->ssr_antenna_model);
  EXPECT_FALSE(findProductSource(kProductSp3 | kProductClk)->ssr_antenna_model);
  EXPECT_FALSE(findProductSource(kProductNav)->ssr_antenna_model);
  // Streamed sources are not known before the run.
  EXPECT_TRUE(findProductSource(0u)->streamed);
  EXPECT_TRUE(findProductSource(kProductLiveSsr)->streamed);
  EXPECT_FALSE(findProductSource(kProductNav)->streamed);
  EXPECT_EQ(findProductSource(kProductSp3 | kProductClk)->phase, SourcePhaseInformation::ClockProducts);
}

TEST(ProductSources, InputsOfNoSourceAreToldWhatTheTableTakes) {
  EXPECT_EQ(findProductSource(kProductSp3), nullptr);
  EXPECT_EQ(findProductSource(kProductSp3 | kProductClk | kProductNav), nullptr);
  EXPECT_EQ(findProductSource(kProductSp3 | kProductClk | kProductSsr), nullptr);
  EXPECT_TRUE(productInputsProblem(kProductNav | kProductSsr).empty());
  const std::string why = productInputsProblem(kProductSp3);
  EXPECT_NE(why.find("inputs SP3 make no product source"), std::string::npos) << why;
  EXPECT_NE(why.find("SP3 + clock (precise)"), std::string::npos) << why;
  EXPECT_NE(why.find("navigation + SSR (broadcast+ssr)"), std::string::npos) << why;
  EXPECT_EQ(why.find("streamed"), std::string::npos) << why;  // no file gives a streamed source
  EXPECT_EQ(productInputNames(kProductSsr | kProductClk), "clock + SSR");
}

TEST(ProductSources, TheInputsOfARunSelectItsRow) {
  PppInputFiles files;
  files.sp3 = {"a.sp3"};
  files.clk = {"a.clk"};
  EXPECT_EQ(productInputsGiven(files), kProductSp3 | kProductClk);
  files.ssr = "s.rtcm3";
  EXPECT_FALSE(productInputsProblem(productInputsGiven(files)).empty());  // SSR corrects broadcast records only
  ProductAssemblyInputs in;
  in.live_ssr = true;
  EXPECT_EQ(selectProductSource(in).name, "live-ssr");
  in.nav = {"n.rnx"};  // files given: the live flag has no say
  EXPECT_EQ(selectProductSource(in).name, "broadcast");
}

TEST(ProductSources, TheAssemblyRefusesInputsOfNoSource) {
  const PppConfig config = bindPppConfig(YAML::Load("{}"), "test");
  ProductAssemblyInputs in;
  in.sp3 = {"a.sp3"};  // without clocks: refused before any file is opened
  try {
    ProductAssembly::assemble(in, config);
    ADD_FAILURE() << "SP3 without clocks was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("product inputs: orbit and clock inputs SP3 make no product source"),
              std::string::npos)
        << e.what();
  }
  ProductAssemblyInputs streamed;  // nothing given: streamed, assembled without files
  const ProductAssembly a = ProductAssembly::assemble(streamed, config);
  EXPECT_EQ(a.ephemeris(), nullptr);
}

}  // namespace
}  // namespace ppp
