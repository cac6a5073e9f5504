// ppp_inspect's library side: file recognition by content and the coverage
// check of observations by precise products, on the shared datasets.
#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>

#include "ppp_bayes_tree/io/transport/file_type.h"
#include "ppp_bayes_tree/app/inspection.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "test_support.h"

using namespace ppp;

TEST(FileType, RecognisedFromTheFirstLine) {
  // First lines as written in the shared files (see ../shared/data).
  EXPECT_EQ(detectFileTypeFromFirstLine(
                "     3.04           OBSERVATION DATA    M: MIXED            RINEX VERSION / TYPE"),
            GnssFileType::RinexObservation);
  EXPECT_EQ(detectFileTypeFromFirstLine(
                "3.0                 COMPACT RINEX FORMAT                    CRINEX VERS   / TYPE"),
            GnssFileType::CompactRinexObservation);
  EXPECT_EQ(detectFileTypeFromFirstLine(
                "     3.00           C                                       RINEX VERSION / TYPE"),
            GnssFileType::RinexClock);
  EXPECT_EQ(detectFileTypeFromFirstLine(
                "     3.04           N: GNSS NAV DATA    M: MIXED            RINEX VERSION / TYPE"),
            GnssFileType::RinexNavigation);
  EXPECT_EQ(detectFileTypeFromFirstLine("#cP2026  5 13  0  0  0.00000000      13 ORBIT IGc20 HLM  IGS"),
            GnssFileType::Sp3);
  EXPECT_EQ(detectFileTypeFromFirstLine("%=BIA 1.00 COD 2026:138:76927 IGS 2026:133:00000"),
            GnssFileType::BiasSinex);
  EXPECT_EQ(detectFileTypeFromFirstLine(
                "     1.4            M                                       ANTEX VERSION / SYST"),
            GnssFileType::Antex);
  EXPECT_EQ(detectFileTypeFromFirstLine("$$ Ocean loading displacement"), GnssFileType::Blq);
  EXPECT_EQ(detectFileTypeFromFirstLine("hello world"), GnssFileType::Unknown);
}

TEST(Inspection, GzipObservationsWithAnyNameAreRecognisedByContent) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string src = test::dataPath("zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx");
  const auto dir = test::tempDir("inspect_gz");
  const std::string gz = (dir / "observations.dat").string();  // name says nothing
  {
    const std::string bytes = test::readFileBytes(src);
    gzFile f = gzopen(gz.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, bytes.data(), static_cast<unsigned>(bytes.size())), static_cast<int>(bytes.size()));
    gzclose(f);
  }
  EXPECT_EQ(detectFileType(gz), GnssFileType::RinexObservation);
  Inspection inspection;
  const FileSummary s = inspection.add(gz);
  EXPECT_EQ(s.epoch_count, 120u);  // 120 epochs (dataset README)
  EXPECT_TRUE(s.report.clean());
  std::filesystem::remove_all(dir);
}

TEST(Inspection, Zim2ProductsCoverItsGpsObservations) {
  PPP_REQUIRE_SHARED_DATA();
  Inspection inspection;
  inspection.add(test::dataPath("zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx"));
  inspection.add(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3"));
  inspection.add(test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK"));
  const std::string report = inspection.coverageReport();
  // The IGS products are GPS only (dataset README); all 14 observed GPS satellites are in them.
  EXPECT_NE(report.find("Galileo: 12 satellite(s) observed, none in the products"), std::string::npos) << report;
  EXPECT_NE(report.find("verdict: the products cover every observed satellite"), std::string::npos) << report;
}

TEST(Inspection, Ccj2ProductsMissTwoGlonassSatellites) {
  PPP_REQUIRE_SHARED_DATA();
  Inspection inspection;
  inspection.add(test::dataPath("ccj2-2021-210/ccj22100.21o"));
  inspection.add(test::dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz"));
  inspection.add(test::dataPath("ccj2-2021-210/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz"));
  const std::string report = inspection.coverageReport();
  // R06 and R10 are observed at CCJ2 but absent from the WUM SP3 satellite list and
  // the CLK PRN LIST; QZSS is not carried by WUM at all.
  EXPECT_NE(report.find("no orbit for: R06 R10"), std::string::npos) << report;
  EXPECT_NE(report.find("no clock for: R06 R10"), std::string::npos) << report;
  EXPECT_NE(report.find("QZSS: 4 satellite(s) observed, none in the products"), std::string::npos) << report;
  EXPECT_NE(report.find("do NOT fully cover"), std::string::npos) << report;
}

TEST(Inspection, UnknownAndMissingFilesGiveClearErrors) {
  const auto dir = test::tempDir("inspect_unknown");
  const std::string path = (dir / "notes.txt").string();
  std::ofstream(path) << "just some text\n";
  Inspection inspection;
  try {
    inspection.add(path);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not a recognised GNSS file"), std::string::npos);
  }
  EXPECT_THROW(inspection.add((dir / "absent.rnx").string()), FileOpenError);
  EXPECT_EQ(inspection.coverageReport(), "");
  std::filesystem::remove_all(dir);
}
