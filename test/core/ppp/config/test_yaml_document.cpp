// One reading of YAML documents for every file the project reads
// (ppp/config/yaml_document.h): a key written twice in one mapping is refused,
// naming the file, the key path and both lines, in configuration files,
// simulation configurations and campaign manifests alike. yaml-cpp itself keeps
// both entries and reads the first, silently.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "ppp_bayes_tree/app/campaign_manifest.h"
#include "ppp_bayes_tree/ppp/config/yaml_document.h"
#include "ppp_bayes_tree/simulation/simulation_config.h"
#include "test_support.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;

/// The error of parseYamlDocument on `text` ("accepted" when none).
std::string errorOf(const std::string& text) {
  try {
    parseYamlDocument(text, "f.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

fs::path writeFile(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

TEST(YamlDocument, KeyWrittenTwiceIsRefusedWithItsPathAndLines) {
  EXPECT_EQ(errorOf("a: 1\nb: 2\na: 3\n"),
            "f.yaml: a: key given twice in one mapping, at line 1 and line 3 (only the first would be read: "
            "remove or merge one of them)");
  EXPECT_NE(errorOf("s:\n  c:\n    i: 1\n    i: 2\n").find("f.yaml: s.c.i: key given twice in one mapping, at line 3 "
                                                          "and line 4"),
            std::string::npos);
  EXPECT_NE(errorOf("l:\n  - {a: 1}\n  - {b: 1, b: 2}\n").find("l[1].b: key given twice in one mapping, at line 3, "
                                                             "columns 6 and 12"),
            std::string::npos)
      << errorOf("l:\n  - {a: 1}\n  - {b: 1, b: 2}\n");
}

TEST(YamlDocument, SameKeyInOtherMappingsAndAliasesAreFine) {
  EXPECT_EQ(errorOf("x: {a: 1}\ny: {a: 1}\nz: [{a: 1}, {a: 2}]\n"), "accepted");
  EXPECT_EQ(errorOf("x: &k {a: 1}\ny: *k\nz: [*k, *k]\n"), "accepted");
  EXPECT_EQ(errorOf("a: 1\n---\na: 1\na: 2\n"), "accepted") << "only the first document is read";
  EXPECT_NE(errorOf("a: [1, 2\n").find("f.yaml: YAML syntax error at line 2"), std::string::npos);
}

TEST(YamlDocument, SimulationConfigWithAKeyTwiceIsRefused) {
  const fs::path path = writeFile(test::tempDir("yaml_document_sim") / "sim.yaml",
                                  "flight:\n  rate_hz: 1\n  rate_hz: 10\n");
  try {
    loadSimulationConfig(path.string());
    ADD_FAILURE() << "accepted: rate_hz 1 (the first) would be used";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.keyPath(), "flight.rate_hz");
    EXPECT_NE(e.reason().find("at line 2 and line 3"), std::string::npos) << e.what();
  }
}

TEST(YamlDocument, CampaignManifestWithAKeyTwiceIsRefused) {
  const fs::path dir = test::tempDir("yaml_document_manifest");
  const fs::path path = writeFile(dir / "manifest.yaml",
                                  "campaign: {name: a, data_root: .}\nbags:\n  - name: f\n    bag: x.bag\n"
                                  "    estimator: ekf\n    estimator: smoother\n");
  try {
    loadCampaignManifest(path.string());
    ADD_FAILURE() << "accepted: estimator ekf (the first) would be used";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.keyPath(), "bags[0].estimator");
    EXPECT_NE(e.reason().find("at line 5 and line 6"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ppp
