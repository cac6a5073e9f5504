// RTCM / IGS SSR: decoder and encoder round trip, real recordings (Swift
// clk.rtcm, the IGS SSRA03IGS0 stream checked against IGS ultra-rapid orbits
// through the ppp_ssr_check core), and bad input (IOD without broadcast record,
// SSR older than its validity, unknown types, truncation, unresolved week).
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/ssr_check.h"
#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ssr_bias_provider.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "fuzz/rtcm_ssr_fuzz_entry.h"
#include "test_support.h"

namespace ppp {
namespace {
using test::dataPath;
using test::gpst;

bool streamsAvailable() { return std::filesystem::is_directory(dataPath("streams/ssr")); }
#define REQUIRE_STREAMS() \
  if (!streamsAvailable()) GTEST_SKIP() << "no ../shared/data/streams (set PPP_SHARED_DATA)"

constexpr double kSemicircle_rad = 3.14159265358979323846;

SatelliteId sat(GnssSystem s, int prn) { return SatelliteId{s, prn}; }

SsrMessage header(GnssSystem system, SsrMessageKind kind, std::uint32_t epoch_s, int igs_subtype = 0) {
  SsrMessage m;
  m.header.system = system;
  m.header.kind = kind;
  m.header.epoch_time_s = epoch_s;
  m.header.update_interval_code = 2;  // 5 s
  m.header.iod_ssr = 3;
  m.header.provider_id = 258;
  m.header.solution_id = 7;
  m.header.igs_subtype = igs_subtype;
  m.header.igs_version = igs_subtype != 0 ? 1 : 0;
  if (kind == SsrMessageKind::Orbit || kind == SsrMessageKind::Combined) m.header.datum_regional = false;
  return m;
}

// Values on the fields' grids (multiples of the LSB), so that the round trip is exact.
SsrOrbitCorrection orbit(const SatelliteId& s, int iod) {
  SsrOrbitCorrection o;
  o.satellite = s;
  o.iod = iod;
  o.radial_m = 1.2345;        // 12345 x 0.1 mm
  o.along_m = -0.4004;        // -1001 x 0.4 mm
  o.cross_m = 0.0808;         // 202 x 0.4 mm
  o.radial_dot_mps = 0.000123;
  o.along_dot_mps = -0.000248;
  o.cross_dot_mps = 0.000004;
  return o;
}
SsrClockCorrection clockCorr(const SatelliteId& s) {
  SsrClockCorrection c;
  c.satellite = s;
  c.c0_m = -0.7531;
  c.c1_m_per_s = 0.000017;
  c.c2_m_per_s2 = 0.00000004;
  return c;
}

std::vector<std::uint8_t> concat(const std::vector<std::vector<std::uint8_t>>& frames) {
  std::vector<std::uint8_t> all;
  for (const auto& f : frames) all.insert(all.end(), f.begin(), f.end());
  return all;
}

TEST(RtcmSsrCodec, RoundTripEveryKindAndSystemRtcmAndIgs) {
  const GnssTime ref = gpst(2026, 7, 7, 14, 0, 0);
  const double sow = ref.gpsWeek().seconds_of_week;
  std::vector<SsrMessage> sent;
  const std::vector<std::pair<GnssSystem, int>> systems = {{GnssSystem::GPS, 5},     {GnssSystem::GLONASS, 7},
                                                           {GnssSystem::Galileo, 11}, {GnssSystem::QZSS, 2},
                                                           {GnssSystem::BeiDou, 23},  {GnssSystem::SBAS, 27}};
  for (const bool igs : {false, true}) {
    for (const auto& entry : systems) {
      // Plain variables, not structured bindings: the lambda below captures sys, which
      // C++17 (and clang before 16) does not allow for a binding.
      const GnssSystem sys = entry.first;
      const int prn = entry.second;
      const SatelliteId s = sat(sys, prn);
      const auto epoch = static_cast<std::uint32_t>(sys == GnssSystem::GLONASS && !igs ? 10800 + 3600 : sow);
      const auto igs_sub = [&](int offset) {
        const int group = sys == GnssSystem::GPS ? 1 : sys == GnssSystem::GLONASS ? 2 : sys == GnssSystem::Galileo ? 3
                        : sys == GnssSystem::QZSS ? 4 : sys == GnssSystem::BeiDou ? 5 : 6;
        return igs ? 20 * group + offset : 0;
      };
      SsrMessage o = header(sys, SsrMessageKind::Orbit, epoch, igs_sub(1));
      o.orbits.push_back(orbit(s, 45));
      if (!igs && sys == GnssSystem::BeiDou) o.orbits.back().iod_aux = 200u;
      if (!igs && sys == GnssSystem::SBAS) o.orbits.back().iod_aux = 0xABCDEFu;
      sent.push_back(o);
      SsrMessage c = header(sys, SsrMessageKind::Clock, epoch, igs_sub(2));
      c.clocks.push_back(clockCorr(s));
      sent.push_back(c);
      SsrMessage oc = header(sys, SsrMessageKind::Combined, epoch, igs_sub(3));
      oc.orbits = o.orbits;
      oc.clocks = c.clocks;
      sent.push_back(oc);
      SsrMessage hr = header(sys, SsrMessageKind::HighRateClock, epoch, igs_sub(4));
      hr.high_rate_clocks.push_back({s, 0.0123});
      sent.push_back(hr);
      SsrMessage cb = header(sys, SsrMessageKind::CodeBias, epoch, igs_sub(5));
      cb.code_biases.push_back({s, {{0, ssrSignalCode(sys, 0, igs), -3.21}, {1, ssrSignalCode(sys, 1, igs), 4.56}}});
      sent.push_back(cb);
      SsrMessage pb = header(sys, SsrMessageKind::PhaseBias, epoch, igs_sub(6));
      pb.dispersive_consistent = true;
      SsrPhaseBias p;
      p.satellite = s;
      p.yaw_rad = 100 * kSemicircle_rad / 256.0;
      p.yaw_rate_rad_per_s = -3 * kSemicircle_rad / 8192.0;
      p.biases.push_back({1, ssrSignalCode(sys, 1, igs), true, 2, 5, -0.1234});
      pb.phase_biases.push_back(p);
      sent.push_back(pb);
      SsrMessage u = header(sys, SsrMessageKind::Ura, epoch, igs_sub(7));
      u.uras.push_back({s, 2, 3, std::nullopt});
      sent.push_back(u);
    }
    SsrMessage v = header(GnssSystem::GPS, SsrMessageKind::Vtec, static_cast<std::uint32_t>(sow), igs ? 201 : 0);
    SsrVtec vtec;
    vtec.quality_tecu = 1.25;
    SsrVtecLayer layer;
    layer.height_m = 450000.0;
    layer.degree = 2;
    layer.order = 1;
    layer.cosine_tecu = {10.0, 1.5, -0.25, 0.005, 0.1};
    layer.sine_tecu = {0.5, -0.75};
    vtec.layers.push_back(layer);
    v.vtec = vtec;
    sent.push_back(v);
  }
  std::vector<std::vector<std::uint8_t>> frames;
  for (const auto& m : sent) frames.push_back(encodeSsrFrame(m));
  const auto bytes = concat(frames);
  const SsrStreamFile got = decodeSsrStream(bytes.data(), bytes.size(), ref);
  EXPECT_EQ(got.counters.totalProblems(), 0u);
  ASSERT_EQ(got.messages.size(), sent.size());
  for (std::size_t i = 0; i < sent.size(); ++i) {
    const SsrMessage& a = sent[i];
    const SsrMessage& b = got.messages[i];
    SCOPED_TRACE("message " + std::to_string(i) + " " + std::string(systemName(a.header.system)) + " " +
                 std::string(ssrMessageKindName(a.header.kind)) + (a.header.igs_subtype ? " IGS" : " RTCM"));
    EXPECT_EQ(b.header.system, a.header.system);
    EXPECT_EQ(b.header.kind, a.header.kind);
    EXPECT_EQ(b.header.epoch_time_s, a.header.epoch_time_s);
    EXPECT_EQ(b.header.update_interval_s, 5.0);
    EXPECT_EQ(b.header.provider_id, 258);
    EXPECT_EQ(b.header.solution_id, 7);
    EXPECT_EQ(b.header.iod_ssr, 3);
    ASSERT_TRUE(b.header.epoch.has_value());
    // Every value back exactly (within rounding of the decimal input).
    ASSERT_EQ(b.orbits.size(), a.orbits.size());
    for (std::size_t k = 0; k < a.orbits.size(); ++k) {
      EXPECT_EQ(b.orbits[k].satellite, a.orbits[k].satellite);
      EXPECT_EQ(b.orbits[k].iod, a.orbits[k].iod);
      EXPECT_EQ(b.orbits[k].iod_aux, a.orbits[k].iod_aux);
      EXPECT_NEAR(b.orbits[k].radial_m, a.orbits[k].radial_m, 1e-9);
      EXPECT_NEAR(b.orbits[k].along_m, a.orbits[k].along_m, 1e-9);
      EXPECT_NEAR(b.orbits[k].cross_m, a.orbits[k].cross_m, 1e-9);
      EXPECT_NEAR(b.orbits[k].radial_dot_mps, a.orbits[k].radial_dot_mps, 1e-12);
      EXPECT_NEAR(b.orbits[k].along_dot_mps, a.orbits[k].along_dot_mps, 1e-12);
      EXPECT_NEAR(b.orbits[k].cross_dot_mps, a.orbits[k].cross_dot_mps, 1e-12);
    }
    ASSERT_EQ(b.clocks.size(), a.clocks.size());
    for (std::size_t k = 0; k < a.clocks.size(); ++k) {
      EXPECT_NEAR(b.clocks[k].c0_m, a.clocks[k].c0_m, 1e-9);
      EXPECT_NEAR(b.clocks[k].c1_m_per_s, a.clocks[k].c1_m_per_s, 1e-12);
      EXPECT_NEAR(b.clocks[k].c2_m_per_s2, a.clocks[k].c2_m_per_s2, 1e-14);
    }
    ASSERT_EQ(b.high_rate_clocks.size(), a.high_rate_clocks.size());
    for (std::size_t k = 0; k < a.high_rate_clocks.size(); ++k)
      EXPECT_NEAR(b.high_rate_clocks[k].clock_m, a.high_rate_clocks[k].clock_m, 1e-9);
    ASSERT_EQ(b.code_biases.size(), a.code_biases.size());
    for (std::size_t k = 0; k < a.code_biases.size(); ++k) {
      ASSERT_EQ(b.code_biases[k].biases.size(), 2u);
      EXPECT_NEAR(b.code_biases[k].biases[0].bias_m, -3.21, 1e-9);
      EXPECT_NEAR(b.code_biases[k].biases[1].bias_m, 4.56, 1e-9);
      EXPECT_EQ(b.code_biases[k].biases[1].code, a.code_biases[k].biases[1].code);
    }
    ASSERT_EQ(b.phase_biases.size(), a.phase_biases.size());
    for (std::size_t k = 0; k < a.phase_biases.size(); ++k) {
      EXPECT_TRUE(b.dispersive_consistent);
      EXPECT_NEAR(b.phase_biases[k].yaw_rad, a.phase_biases[k].yaw_rad, 1e-12);
      EXPECT_NEAR(b.phase_biases[k].yaw_rate_rad_per_s, a.phase_biases[k].yaw_rate_rad_per_s, 1e-12);
      const auto& pa = a.phase_biases[k].biases[0];
      const auto& pb2 = b.phase_biases[k].biases[0];
      EXPECT_EQ(pb2.integer, pa.integer);
      EXPECT_EQ(pb2.widelane_integer, pa.widelane_integer);
      EXPECT_EQ(pb2.discontinuity_counter, pa.discontinuity_counter);
      EXPECT_NEAR(pb2.bias_m, pa.bias_m, 1e-9);
    }
    ASSERT_EQ(b.uras.size(), a.uras.size());
    for (std::size_t k = 0; k < a.uras.size(); ++k) {
      EXPECT_EQ(b.uras[k].ura_class, 2);
      EXPECT_EQ(b.uras[k].ura_value, 3);
      // RTCM DF389: 3^class (1 + value/4) - 1 mm = 9 x 1.75 - 1 = 14.75 mm.
      ASSERT_TRUE(b.uras[k].ura_m.has_value());
      EXPECT_NEAR(*b.uras[k].ura_m, 0.01475, 1e-12);
    }
    EXPECT_EQ(b.vtec.has_value(), a.vtec.has_value());
    if (a.vtec) {
      EXPECT_NEAR(b.vtec->quality_tecu, 1.25, 1e-9);
      ASSERT_EQ(b.vtec->layers.size(), 1u);
      EXPECT_NEAR(b.vtec->layers[0].height_m, 450000.0, 1e-6);
      EXPECT_EQ(b.vtec->layers[0].cosine_tecu.size(), 5u);  // n = 0..2, m = 0..min(n,1)
      EXPECT_EQ(b.vtec->layers[0].sine_tecu.size(), 2u);
      for (std::size_t k = 0; k < 5; ++k) EXPECT_NEAR(b.vtec->layers[0].cosine_tecu[k], a.vtec->layers[0].cosine_tecu[k], 1e-9);
    }
    // Re-encoding the decoded message gives the same bytes.
    EXPECT_EQ(encodeSsrFrame(b), frames[i]);
  }
}

TEST(RtcmSsrCodec, EpochTimesPlacedByTheirSystemsTimeScales) {
  const GnssTime ref = gpst(2026, 7, 7, 23, 50, 0);
  const double sow = ref.gpsWeek().seconds_of_week;
  // GPS 23:59:50 (same day), BeiDou BDT = GPST - 14 s, GLONASS time of day = UTC + 3 h.
  SsrMessage g = header(GnssSystem::GPS, SsrMessageKind::Clock, static_cast<std::uint32_t>(sow + 590));
  g.clocks.push_back(clockCorr(sat(GnssSystem::GPS, 1)));
  SsrMessage c = header(GnssSystem::BeiDou, SsrMessageKind::Clock, static_cast<std::uint32_t>(sow + 590 - 14));
  c.clocks.push_back(clockCorr(sat(GnssSystem::BeiDou, 20)));
  // 2026-07-07 23:59:50 GPST = 23:59:32 UTC (TAI-UTC 37 s) = 02:59:32 GLONASS on 07-08.
  SsrMessage r = header(GnssSystem::GLONASS, SsrMessageKind::Clock, 2 * 3600 + 59 * 60 + 32);
  r.clocks.push_back(clockCorr(sat(GnssSystem::GLONASS, 3)));
  const auto bytes = concat({encodeSsrFrame(g), encodeSsrFrame(c), encodeSsrFrame(r)});
  const SsrStreamFile got = decodeSsrStream(bytes.data(), bytes.size(), ref);
  ASSERT_EQ(got.messages.size(), 3u);
  const GnssTime expected = gpst(2026, 7, 7, 23, 59, 50);
  for (const auto& m : got.messages) {
    ASSERT_TRUE(m.header.epoch.has_value());
    EXPECT_EQ(*m.header.epoch, expected) << systemName(m.header.system) << " " << m.header.epoch->toString();
  }
}

TEST(RtcmSsrDecoderBadInput, UnknownTypesTruncatedMessagesAndMissingWeekAreCounted) {
  const GnssTime ref = gpst(2026, 7, 7, 14, 0, 0);
  const auto sow = static_cast<std::uint32_t>(ref.gpsWeek().seconds_of_week);
  SsrMessage good = header(GnssSystem::GPS, SsrMessageKind::Clock, sow);
  good.clocks.push_back(clockCorr(sat(GnssSystem::GPS, 9)));
  // A station message (not SSR) and an IGS-SSR message with an undefined sub-type.
  BitWriter station;
  station.putUnsigned(1005, 12);
  for (int i = 0; i < 5; ++i) station.putUnsigned(0, 28);
  BitWriter igs_bad;
  igs_bad.putUnsigned(4076, 12);
  igs_bad.putUnsigned(1, 3);
  igs_bad.putUnsigned(99, 8);
  igs_bad.putUnsigned(0, 40);
  // A clock message claiming 5 satellites but holding one.
  auto truncated = encodeSsrPayload(good);
  {
    BitWriter w;
    SsrMessage five = good;
    for (int i = 0; i < 4; ++i) five.clocks.push_back(clockCorr(sat(GnssSystem::GPS, 10 + i)));
    auto payload = encodeSsrPayload(five);
    payload.resize(truncated.size());
    truncated = payload;
  }
  const auto bytes = concat({encodeSsrFrame(good), encodeRtcm3Frame(station.bytes()), encodeRtcm3Frame(igs_bad.bytes()),
                             encodeRtcm3Frame(truncated), encodeSsrFrame(good)});
  const SsrStreamFile got = decodeSsrStream(bytes.data(), bytes.size(), ref);
  EXPECT_EQ(got.messages.size(), 2u);  // the good ones go on
  // The station message is a receiver's (counted apart, no problem); the IGS-SSR sub-type is unknown.
  EXPECT_EQ(got.receiver_messages_by_type, (std::map<int, std::uint64_t>{{1005, 1}}));
  EXPECT_EQ(got.counters.count(StreamProblemKind::UnknownMessage), 1u);
  EXPECT_EQ(got.counters.count(StreamProblemKind::MalformedMessage), 1u);
  bool saw_igs_subtype = false, saw_truncated = false;
  for (const auto& p : got.counters.problems) {
    if (p.kind == StreamProblemKind::UnknownMessage && p.message_type == 4076) {
      saw_igs_subtype = true;
      EXPECT_EQ(p.frame_index, 2u);
    }
    if (p.kind == StreamProblemKind::MalformedMessage) {
      saw_truncated = true;
      EXPECT_EQ(p.frame_index, 3u);
      EXPECT_EQ(p.message_type, 1058);
      EXPECT_NE(p.describe().find("byte "), std::string::npos);
    }
  }
  EXPECT_TRUE(saw_igs_subtype);
  EXPECT_TRUE(saw_truncated);

  // Without a reference time the epoch cannot be placed: counted, values kept.
  const SsrStreamFile weekless = decodeSsrStream(bytes.data(), bytes.size(), std::nullopt);
  EXPECT_EQ(weekless.counters.count(StreamProblemKind::UnresolvedTime), 2u);
  ASSERT_EQ(weekless.messages.size(), 2u);
  EXPECT_FALSE(weekless.messages[0].header.epoch.has_value());
  EXPECT_NEAR(weekless.messages[0].clocks[0].c0_m, -0.7531, 1e-9);
}

TEST(RtcmSsrDecoder, SwiftClkRecordingEveryTypeCountedAndPhysical) {
  REQUIRE_STREAMS();
  // The date is not recorded: decoded without a week (epochs unresolved, values kept).
  const SsrStreamFile f = readSsrStreamFile(dataPath("streams/rtcm/clk.rtcm"), std::nullopt);
  EXPECT_EQ(f.counters.count(StreamProblemKind::ChecksumError), 0u);
  EXPECT_EQ(f.counters.count(StreamProblemKind::MalformedMessage), 0u);
  EXPECT_EQ(f.counters.count(StreamProblemKind::UnknownMessage), 0u);
  for (const int type : {1059, 1060, 1065, 1066, 1242, 1243, 1260, 1261, 1264, 1265, 1267, 1270}) {
    const auto it = f.summary.messages_by_type.find(type);
    EXPECT_TRUE(it != f.summary.messages_by_type.end() && it->second > 0) << "type " << type;
  }
  EXPECT_EQ(f.summary.messages, f.counters.frames);  // every frame is an SSR message and decoded
  std::size_t orbits = 0, clocks = 0, code = 0, phase = 0, vtec = 0;
  for (const auto& m : f.messages) {
    EXPECT_EQ(m.header.update_interval_s, m.header.kind == SsrMessageKind::Vtec ? 60.0 : 5.0);
    for (const auto& o : m.orbits) {
      ++orbits;
      // SSR orbit corrections are broadcast orbit errors: metres at most.
      EXPECT_LT(std::abs(o.radial_m), 30.0) << o.satellite.toString();
      EXPECT_LT(std::abs(o.along_m), 30.0) << o.satellite.toString();
      EXPECT_LT(std::abs(o.cross_m), 30.0) << o.satellite.toString();
      EXPECT_LT(std::abs(o.radial_dot_mps), 0.05);
    }
    for (const auto& c : m.clocks) {
      ++clocks;
      EXPECT_LT(std::abs(c.c0_m), 100.0) << c.satellite.toString();
    }
    for (const auto& b : m.code_biases)
      for (const auto& s : b.biases) {
        ++code;
        EXPECT_LT(std::abs(s.bias_m), 50.0);
        EXPECT_TRUE(s.code.has_value()) << b.satellite.toString() << " signal id " << s.signal_id;
      }
    for (const auto& b : m.phase_biases) {
      EXPECT_GE(b.yaw_rad, 0.0);
      EXPECT_LT(b.yaw_rad, 2.0 * kSemicircle_rad);
      for (const auto& s : b.biases) {
        ++phase;
        EXPECT_LT(std::abs(s.bias_m), 50.0);
        EXPECT_TRUE(s.code.has_value()) << b.satellite.toString() << " signal id " << s.signal_id;
      }
    }
    if (m.vtec) {
      ++vtec;
      ASSERT_FALSE(m.vtec->layers.empty());
      EXPECT_GT(m.vtec->layers[0].height_m, 100e3);
      EXPECT_LT(m.vtec->layers[0].height_m, 2000e3);
      EXPECT_GT(m.vtec->layers[0].cosine_tecu[0], 0.0);  // the mean VTEC term is positive
    }
  }
  EXPECT_GT(orbits, 1000u);
  EXPECT_EQ(clocks, orbits);  // combined messages only
  EXPECT_GT(code, 1000u);
  EXPECT_GT(phase, 1000u);
  EXPECT_GT(vtec, 0u);
}

struct IgsSsrFiles {
  std::string nav = dataPath("streams/ssr/BRDC00WRD_S_20261880000_01D_MN_GPS_SSR_20261881400.rnx");
  std::string ssr = dataPath("streams/ssr/SSRA03IGS0_2026188140760_3epoch.rtcm3");
  std::string sp3 = dataPath("streams/ssr/IGS0OPSULT_20261870600_02D_15M_ORB_20261881315_07E.SP3");
  std::string atx = dataPath("antex/igs20_gps_satellites_trim.atx");
};

TEST(SsrCheckRealData, IgsSsraStreamAgreesWithUltraRapidOrbits) {
  REQUIRE_STREAMS();
  const IgsSsrFiles files;
  SsrCheckRequest req;
  req.nav = {files.nav};
  req.ssr = files.ssr;
  req.sp3 = files.sp3;
  req.atx = files.atx;
  const SsrCheckResult r = checkSsrAgainstSp3(req);
  std::cout << formatSsrCheck(r);
  EXPECT_EQ(r.reference, EphemerisReference::AntennaPhaseCentreL1);  // from the SSRA name: the L1 phase centre
  // 30 GPS satellites at the stream's orbit epochs.
  EXPECT_GE(r.satellite_epochs, 90u);
  EXPECT_EQ(r.satellites.size(), 30u);
  EXPECT_LT(r.orbit_rms_3d_m, 0.15);
  EXPECT_LT(r.clock_rms_ns, 3.0);  // ultra-rapid clocks here are predictions
  EXPECT_TRUE(std::regex_match(r.lastLine(), std::regex(R"(orbit 3D RMS [0-9.]+ m, clock RMS [0-9.]+ ns, [0-9]+ satellite-epochs)")));

  // The Galileo and BeiDou messages decode and are counted.
  const SsrStreamFile f = readSsrStreamFile(files.ssr, gpst(2026, 7, 7, 14, 0, 0));
  // No problems; the GPS C1C id sent twice by satellites with L5 is counted
  // apart (the decoder keeps the first value; test_ssr_conventions_real_data).
  EXPECT_EQ(f.counters.totalProblems(), 0u);
  EXPECT_GT(f.counters.repeated_signals, 0u);
  for (const int type : {1059, 1060, 1065, 1066, 1242, 1243, 1260, 1261})
    EXPECT_GT(f.summary.messages_by_type.count(type), 0u) << type;
  EXPECT_EQ(f.summary.satellites.at(GnssSystem::Galileo).size(), 27u);
  EXPECT_EQ(f.summary.satellites.at(GnssSystem::BeiDou).size(), 23u);

  // The check tells a wrong reference point: treated as centre of mass (no
  // PCO), the SP3 and the stream differ by the satellite antenna offsets (~1-2 m).
  req.reference = EphemerisReference::CentreOfMass;
  EXPECT_GT(checkSsrAgainstSp3(req).orbit_rms_3d_m, 0.5);
}

TEST(BroadcastSsrEphemeris, IodWithoutBroadcastRecordAndTooOldCorrectionsExcludeOnlyThatSatellite) {
  REQUIRE_STREAMS();
  const IgsSsrFiles files;
  const NavData nav = readRinexNav(files.nav);
  // G06 has IODE 38 in the file, G09 IODE 89; G06 is sent with an IOD no record has.
  const GnssTime t0 = gpst(2026, 7, 7, 14, 7, 40);
  SsrMessage m = header(GnssSystem::GPS, SsrMessageKind::Combined, static_cast<std::uint32_t>(t0.gpsWeek().seconds_of_week));
  m.orbits = {orbit(sat(GnssSystem::GPS, 6), 200), orbit(sat(GnssSystem::GPS, 9), 89)};
  m.clocks = {clockCorr(sat(GnssSystem::GPS, 6)), clockCorr(sat(GnssSystem::GPS, 9))};
  const auto bytes = encodeSsrFrame(m);
  const SsrStreamFile f = decodeSsrStream(bytes.data(), bytes.size(), t0);
  auto store = std::make_shared<SsrCorrectionStore>();
  for (const auto& msg : f.messages) store->add(msg);
  const BroadcastSsrEphemeris eph({nav}, store, {});
  ASSERT_EQ(eph.consistency().count(StreamProblemKind::SsrWithoutBroadcast), 1u);
  EXPECT_EQ(eph.consistency().problems[0].frame_index, 0u);
  EXPECT_NE(eph.consistency().problems[0].detail.find("G06 IOD 200"), std::string::npos);

  const auto g06 = eph.satelliteOrbit(sat(GnssSystem::GPS, 6), t0 + 2.0);
  EXPECT_FALSE(g06.ok());
  EXPECT_EQ(g06.reason, EphemerisUnavailable::NoValidRecord);
  const auto g09 = eph.correctedState(sat(GnssSystem::GPS, 9), t0 + 2.0);
  ASSERT_TRUE(g09.ok()) << g09.detail;
  // The correction applied: |X_brdc - X| = |RAC correction| at t0 + 2 s.
  const SsrOrbitCorrection o = orbit(sat(GnssSystem::GPS, 9), 89);
  const Eigen::Vector3d rac(o.radial_m + 2 * o.radial_dot_mps, o.along_m + 2 * o.along_dot_mps, o.cross_m + 2 * o.cross_dot_mps);
  EXPECT_NEAR((g09.value->broadcast.position_ecef_m - g09.value->position_ecef_m).norm(), rac.norm(), 1e-6);
  // Radial: the corrected position is LOWER by the radial correction (X = X_brdc - e_r dr).
  const Eigen::Vector3d& rb = g09.value->broadcast.position_ecef_m;
  EXPECT_NEAR(rb.norm() - g09.value->position_ecef_m.norm(), rac.x(), 2e-3);
  // Clock: dt = dt_brdc + dC / c.
  const SsrClockCorrection c = clockCorr(sat(GnssSystem::GPS, 9));
  const double dc_m = c.c0_m + 2 * c.c1_m_per_s + 4 * c.c2_m_per_s2;
  EXPECT_NEAR((g09.value->clock_s - (g09.value->broadcast.clock_bias_s - g09.value->broadcast.relativistic_s)) * 299792458.0,
              dc_m, 1e-6);

  // Older than its validity (max(90 s, 2 x 5 s)): unavailable, with the reason.
  const auto old = eph.satelliteOrbit(sat(GnssSystem::GPS, 9), t0 + 91.0);
  EXPECT_FALSE(old.ok());
  EXPECT_EQ(old.reason, EphemerisUnavailable::OutsideSpan);
  EXPECT_NE(old.detail.find("older than its validity"), std::string::npos);
  EXPECT_TRUE(eph.satelliteOrbit(sat(GnssSystem::GPS, 9), t0 + 89.0).ok());
  // Before the first correction: none.
  EXPECT_FALSE(eph.satelliteOrbit(sat(GnssSystem::GPS, 9), t0 - 1.0).ok());
}

TEST(SsrBiasProvider, NegatesSsrBiasesIntoOsbConvention) {
  const GnssTime t0 = gpst(2026, 7, 7, 14, 0, 0);
  SsrMessage cb = header(GnssSystem::GPS, SsrMessageKind::CodeBias, static_cast<std::uint32_t>(t0.gpsWeek().seconds_of_week));
  cb.header.epoch = t0;
  cb.code_biases.push_back({sat(GnssSystem::GPS, 3), {{0, ssrSignalCode(GnssSystem::GPS, 0, false), 1.9}}});
  auto store = std::make_shared<SsrCorrectionStore>();
  ASSERT_TRUE(store->add(cb));
  const SsrBiasProvider biases(store, "test");
  const auto c1c = *ObservationCode::parse("C1C");
  const BiasAnswer a = biases.codeBias(sat(GnssSystem::GPS, 3), c1c, t0 + 10.0);
  ASSERT_TRUE(a.value_m.has_value());
  EXPECT_DOUBLE_EQ(*a.value_m, -1.9);
  EXPECT_FALSE(biases.codeBias(sat(GnssSystem::GPS, 3), *ObservationCode::parse("C2W"), t0 + 10.0).value_m);
  EXPECT_FALSE(biases.codeBias(sat(GnssSystem::GPS, 3), c1c, t0 - 10.0).value_m);
}

TEST(SsrBiasProvider, CodeBiasesArrivingOlderThanTheirValidityAreInForceFromTheirArrival) {
  // A service that re-sends the code biases with the epoch of their issue,
  // hours old (the Galileo HAS internet distribution does): in stream order
  // after an orbit message of t0, each copy is in force from t0 on.
  const GnssTime t0 = gpst(2026, 7, 7, 14, 0, 0), issued = t0 - 12.0 * 3600.0;
  const auto c1c = *ObservationCode::parse("C1C");
  const auto l1c = *ObservationCode::parse("L1C");
  SsrMessage o = header(GnssSystem::GPS, SsrMessageKind::Orbit, 0);
  o.header.epoch = t0;
  o.orbits.push_back(orbit(sat(GnssSystem::GPS, 3), 1));
  SsrMessage cb = header(GnssSystem::GPS, SsrMessageKind::CodeBias, 0);
  cb.header.epoch = issued;
  cb.code_biases.push_back({sat(GnssSystem::GPS, 3), {{0, ssrSignalCode(GnssSystem::GPS, 0, false), 1.9}}});
  SsrMessage pb = header(GnssSystem::GPS, SsrMessageKind::PhaseBias, 0);
  pb.header.epoch = issued;
  SsrPhaseBias p{};
  p.satellite = sat(GnssSystem::GPS, 3);
  SsrSignalPhaseBias s{};
  s.signal_id = 0;
  s.code = ssrSignalCode(GnssSystem::GPS, 0, false);
  s.code->type = ObservableType::CarrierPhase;
  s.bias_m = 0.3;
  p.biases.push_back(s);
  pb.phase_biases.push_back(p);

  auto store = std::make_shared<SsrCorrectionStore>();
  ASSERT_TRUE(store->add(cb));  // before any other epoch: at its own, too old for any later instant
  EXPECT_EQ(store->staleCodeBiasMessages(), 0u);
  const SsrBiasProvider biases(store, "test");
  EXPECT_FALSE(biases.codeBias(sat(GnssSystem::GPS, 3), c1c, t0).value_m);
  ASSERT_TRUE(store->add(o));
  ASSERT_TRUE(store->add(cb));  // re-sent after the orbits of t0
  ASSERT_TRUE(store->add(pb));
  EXPECT_EQ(store->staleCodeBiasMessages(), 1u);
  EXPECT_NE(store->firstStaleCodeBiasMessage().find("43200 s later"), std::string::npos)
      << store->firstStaleCodeBiasMessage();
  const BiasAnswer a = biases.codeBias(sat(GnssSystem::GPS, 3), c1c, t0 + 10.0);
  ASSERT_TRUE(a.value_m.has_value());
  EXPECT_DOUBLE_EQ(*a.value_m, -1.9);
  EXPECT_EQ(a.valid_from, t0);
  EXPECT_EQ(a.valid_until, t0 + 3600.0);  // the bias age limit, from the arrival
  EXPECT_FALSE(biases.codeBias(sat(GnssSystem::GPS, 3), c1c, t0 + 3601.0).value_m);
  // A phase bias that old stays unused: a fix must not rest on it.
  EXPECT_FALSE(biases.phaseBias(sat(GnssSystem::GPS, 3), l1c, t0 + 10.0).value_m);
  // A current set (epoch within its validity on arrival) keeps its own epoch.
  SsrMessage fresh = cb;
  fresh.header.epoch = t0 + 5.0;
  fresh.code_biases.front().biases.front().bias_m = 2.0;
  ASSERT_TRUE(store->add(fresh));
  EXPECT_EQ(store->staleCodeBiasMessages(), 1u);
  EXPECT_EQ(biases.codeBias(sat(GnssSystem::GPS, 3), c1c, t0 + 6.0).valid_from, t0 + 5.0);
  EXPECT_DOUBLE_EQ(*biases.codeBias(sat(GnssSystem::GPS, 3), c1c, t0 + 6.0).value_m, -2.0);
}

TEST(SsrBiasProvider, GpsPyCodesTakeTheBiasOfAnotherTrackingOfTheSameCode) {
  // A stream that sends "L2 P" (id 10) serves the C2W (Z-tracking) a receiver
  // records; its own signal always comes first. GLONASS P is another signal family.
  const GnssTime t0 = gpst(2026, 7, 7, 14, 0, 0);
  SsrMessage cb = header(GnssSystem::GPS, SsrMessageKind::CodeBias, 0);
  cb.header.epoch = t0;
  cb.code_biases.push_back({sat(GnssSystem::GPS, 3),
                            {{10, ssrSignalCode(GnssSystem::GPS, 10, false), 2.5},
                             {0, ssrSignalCode(GnssSystem::GPS, 0, false), 1.5}}});
  cb.code_biases.push_back({sat(GnssSystem::GPS, 4),
                            {{10, ssrSignalCode(GnssSystem::GPS, 10, false), 2.5},
                             {11, ssrSignalCode(GnssSystem::GPS, 11, false), 2.4}}});
  auto store = std::make_shared<SsrCorrectionStore>();
  ASSERT_TRUE(store->add(cb));
  const SsrBiasProvider biases(store, "test");
  const auto value = [&](int prn, const char* code) {
    return biases.codeBias(sat(GnssSystem::GPS, prn), *ObservationCode::parse(code), t0).value_m;
  };
  EXPECT_DOUBLE_EQ(*value(3, "C2W"), -2.5);
  EXPECT_DOUBLE_EQ(*value(3, "C2Y"), -2.5);
  EXPECT_DOUBLE_EQ(*value(3, "C2P"), -2.5);
  EXPECT_FALSE(value(3, "C2L"));  // L2C is another signal
  EXPECT_FALSE(value(3, "C1W"));  // another band
  EXPECT_DOUBLE_EQ(*value(4, "C2W"), -2.4);  // its own first
  EXPECT_DOUBLE_EQ(*value(4, "C2P"), -2.5);
}

TEST(SsrConfig, AgeLimitsAreBoundStrictly) {
  const PppConfig defaults = parsePppConfig("{}", "x.yaml");
  EXPECT_EQ(defaults.ssr.orbit_max_age_s, 90.0);
  EXPECT_EQ(defaults.ssr.high_rate_clock_max_age_s, 10.0);
  const PppConfig c = parsePppConfig("ssr: {orbit_max_age_s: 30, clock_max_age_s: 12.5, bias_max_age_s: 600}", "x.yaml");
  EXPECT_EQ(c.ssr.orbit_max_age_s, 30.0);
  EXPECT_EQ(c.ssr.clock_max_age_s, 12.5);
  EXPECT_EQ(c.ssr.bias_max_age_s, 600.0);
  EXPECT_THROW(parsePppConfig("ssr: {orbit_max_age_s: -1}", "x.yaml"), ConfigError);
  EXPECT_THROW(parsePppConfig("ssr: {orbit_age: 10}", "x.yaml"), ConfigError);
  // The limit acts: a correction of update interval 5 s is valid for max(30, 10) s.
  SsrCorrectionStore store(c.ssr);
  SsrMessage m = header(GnssSystem::GPS, SsrMessageKind::Orbit, 0);
  m.header.epoch = test::gpst(2026, 1, 1);
  m.header.update_interval_s = 5.0;
  m.orbits.push_back(orbit(sat(GnssSystem::GPS, 1), 1));
  ASSERT_TRUE(store.add(m));
  EXPECT_TRUE(store.orbit(sat(GnssSystem::GPS, 1), *m.header.epoch + 30.0));
  const auto old = store.orbit(sat(GnssSystem::GPS, 1), *m.header.epoch + 31.0);
  EXPECT_FALSE(old);
  EXPECT_TRUE(old.too_old);
}

// The fuzz entry over its generated seed corpus (test/fuzz/corpus/rtcm_ssr,
// written by the encoder: every kind, IGS-SSR, VTEC, garbage/CRC/truncation),
// so that the entry builds with the normal tests and the seeds run clean.
TEST(RtcmSsrFuzzCorpus, SeedsRunThroughTheFuzzEntry) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(PPP_FUZZ_DIR) + "/corpus/rtcm_ssr")) {
    const std::string bytes = test::readFileBytes(e.path().string());
    EXPECT_NO_THROW(fuzz::fuzzRtcmSsr(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) << e.path();
    ++n;
  }
  EXPECT_GE(n, 5u);
}

}  // namespace
}  // namespace ppp
