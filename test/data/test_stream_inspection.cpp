// ppp_stream_inspect's summary (app/stream_inspection.h) of the three kinds of
// recordings: UBX (RXM-RAWX + SFRBX with NMEA between), RTCM 3 SSR (the SSR
// decoder's block), and ppp_inspect's view of a UBX file.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/app/inspection.h"
#include "ppp_bayes_tree/app/stream_convert.h"
#include "ppp_bayes_tree/app/stream_inspection.h"
#include "ppp_bayes_tree/io/rinex/observation_source.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "test_support.h"

namespace ppp {
namespace {

TEST(StreamInspection, UbxRecordingEpochsRateSignalsAndEphemerides) {
  if (!test::sharedDataAvailable()) GTEST_SKIP() << "no ../shared/data (set PPP_SHARED_DATA)";
  const StreamInspection s = inspectStreamFile(test::dataPath("streams/ubx/gnss_1730.ubx"));
  EXPECT_EQ(s.format, StreamFormat::Ubx);
  // README: 536 RXM-RAWX epochs at 4 Hz, 17:30:39-17:32:53 GPST; no GLONASS.
  EXPECT_EQ(s.epochs, 536u);
  ASSERT_TRUE(s.interval_s.has_value());
  EXPECT_DOUBLE_EQ(*s.interval_s, 0.25);
  EXPECT_EQ(s.counters.frames_by_type.at(0x0215), 536u);   // RXM-RAWX
  EXPECT_EQ(s.counters.frames_by_type.at(0x0213), 2328u);  // RXM-SFRBX
  EXPECT_EQ(s.satellites.count(GnssSystem::GLONASS), 0u);
  EXPECT_GT(s.ephemeris_records.at(GnssSystem::GPS), 0u);
  EXPECT_GT(s.ephemeris_records.at(GnssSystem::Galileo), 0u);
  EXPECT_EQ(s.counters.totalProblems(), 0u) << "NMEA between frames is not a problem";
  const std::string text = formatStreamInspection(s);
  EXPECT_NE(text.find("4.00 Hz"), std::string::npos) << text;
  // ppp_inspect recognises the file and summarises it the same way.
  Inspection inspection;
  const FileSummary f = inspection.add(test::dataPath("streams/ubx/gnss_1730.ubx"));
  EXPECT_EQ(f.epoch_count, 536u);
}

TEST(StreamInspection, SsrStreamGetsTheSsrDecodersBlock) {
  if (!test::sharedDataAvailable()) GTEST_SKIP() << "no ../shared/data (set PPP_SHARED_DATA)";
  Rtcm3DecoderOptions options;
  options.reference_time = parseReferenceDate("2026/07/07");
  const StreamInspection s =
      inspectStreamFile(test::dataPath("streams/ssr/SSRA03IGS0_2026188140760_3epoch.rtcm3"), options);
  EXPECT_EQ(s.format, StreamFormat::Rtcm3);
  EXPECT_EQ(s.epochs, 0u);  // corrections only
  ASSERT_FALSE(s.ssr.empty());
  std::string block;
  for (const auto& line : s.ssr) block += line + "\n";
  // README: GPS 1059/1060/1065/1066, Galileo 1242/1243, BeiDou 1260/1261, 10-s updates.
  for (const char* type : {"1059", "1060", "1242", "1243", "1260", "1261"})
    EXPECT_NE(block.find(type), std::string::npos) << block;
  EXPECT_NE(block.find("10 s"), std::string::npos) << block;
  EXPECT_EQ(s.counters.count(StreamProblemKind::UnknownMessage), 0u);
  EXPECT_EQ(s.counters.count(StreamProblemKind::ChecksumError), 0u);
}

TEST(StreamConvert, UbxToRinexReadsBackWithTheSameEpochs) {
  if (!test::sharedDataAvailable()) GTEST_SKIP() << "no ../shared/data (set PPP_SHARED_DATA)";
  const auto dir = test::tempDir("ubx_convert");
  const std::string obs = (dir / "walk.obs").string(), nav = (dir / "walk.nav").string();
  const StreamConversion c = convertStreamToRinex(test::dataPath("streams/ubx/gnss_1730.ubx"), obs, nav, {});
  EXPECT_EQ(c.format, StreamFormat::Ubx);
  EXPECT_EQ(c.epochs, 536u);
  EXPECT_EQ(c.navigation_records, 11u);  // 4 GPS + 7 Galileo records from SFRBX (test_ubx_decoder)
  RinexObservationSource reader(obs);
  ObsEpoch epoch;
  std::size_t n = 0;
  while (reader.next(epoch) == ObservationRead::Epoch) ++n;
  EXPECT_EQ(n, 536u);
}

}  // namespace
}  // namespace ppp
