// RTCM 3 ephemeris encoder (io/rtcm/rtcm3_ephemeris_encoder.h): the 1019/1042/1044/
// 1045/1046 frames of the real STR2 recording re-encoded bit for bit; 1019/1045/1046 for
// every real record of the ESBC 2020-177 broadcast file, 1020 for the GLONASS
// records of the STR2 and GMSD recordings (the ESBC file has no GLONASS),
// encoded, framed and decoded again by our Rtcm3Decoder, and by the peer:
// RTKLIB convbin (Debian rtklib 2.4.3 b34) turns the encoded stream into a
// RINEX navigation file whose records equal the source to the printed precision.
//
// Broadcast values already lie on the ICD grid that the RTCM fields share
// (IS-GPS-200 table 20-III, Galileo OS SIS ICD table 60), so the round trip is
// exact up to the printed digits of the RINEX file; the test allows half a
// field step. Differences by design (the message cannot carry them), counted
// and named:
//  - GPS URA: RINEX 2.0 m is index 0, read back as its table value 2.4 m;
//  - GPS fit interval: a flag, "4 h" or "more than 4 h" (our decoder: 6 h);
//  - Galileo data sources: fixed per message type (1045: 258, 1046: 517), where
//    the file has e.g. 513 (E1-B only) or 516 (E5b only);
//  - the transmission time of message (no field): convbin writes its own
//    stream time; our decoder leaves it absent.
// GLONASS: convbin run on STR2's own 1020 frames and on ours re-encoded from
// our decoding of them gives the same records (matched by slot, tb and tk).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_ephemeris_encoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;

std::string esbcNav() { return test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_MN.rnx"); }
double p2(int e) { return std::ldexp(1.0, e); }
bool haveConvbin() { return std::system("command -v convbin > /dev/null 2>&1") == 0; }

/// Largest |a - b| / step over the compared fields, and where.
struct Worst {
  double steps = 0.0;
  std::string where;
  void add(double a, double b, double step, const std::string& what) {
    const double s = std::abs(a - b) / step;
    if (s > steps) {
      steps = s;
      where = what;
    }
  }
};

void addKepler(Worst& w, const KeplerOrbit& a, const KeplerOrbit& b, const std::string& id) {
  w.add(a.crs_m, b.crs_m, p2(-5), id + " crs");
  w.add(a.delta_n_radps, b.delta_n_radps, p2(-43) * kPi, id + " delta n");
  w.add(a.m0_rad, b.m0_rad, p2(-31) * kPi, id + " M0");
  w.add(a.cuc_rad, b.cuc_rad, p2(-29), id + " cuc");
  w.add(a.eccentricity, b.eccentricity, p2(-33), id + " e");
  w.add(a.cus_rad, b.cus_rad, p2(-29), id + " cus");
  w.add(a.sqrt_a_sqrtm, b.sqrt_a_sqrtm, p2(-19), id + " sqrt A");
  w.add(a.cic_rad, b.cic_rad, p2(-29), id + " cic");
  w.add(a.omega0_rad, b.omega0_rad, p2(-31) * kPi, id + " Omega0");
  w.add(a.cis_rad, b.cis_rad, p2(-29), id + " cis");
  w.add(a.i0_rad, b.i0_rad, p2(-31) * kPi, id + " i0");
  w.add(a.crc_m, b.crc_m, p2(-5), id + " crc");
  w.add(a.omega_rad, b.omega_rad, p2(-31) * kPi, id + " omega");
  w.add(a.omega_dot_radps, b.omega_dot_radps, p2(-43) * kPi, id + " Omega dot");
  w.add(a.idot_radps, b.idot_radps, p2(-43) * kPi, id + " IDOT");
  w.add(a.toe_sow, b.toe_sow, 1.0, id + " toe");
  w.add(a.toe.toGpsSecondsDouble(), b.toe.toGpsSecondsDouble(), 1.0, id + " toe (GPST)");
}

/// The frames of every record, decoded by a fresh decoder near `reference`.
Rtcm3Output decodeFrames(const std::vector<std::vector<std::uint8_t>>& payloads, const GnssTime& reference,
                         StreamCounters* counters = nullptr) {
  Rtcm3DecoderOptions options;
  options.reference_time = reference;
  Rtcm3Decoder decoder(options);
  for (const auto& p : payloads) {
    const auto frame = encodeRtcm3Frame(p);
    decoder.feed(frame.data(), frame.size());
  }
  decoder.finish();
  if (counters) *counters = decoder.counters();
  return decoder.output();
}

TEST(Rtcm3EphemerisEncoder, EveryEsbcGpsAndGalileoRecordRoundTripsWithinItsQuantisation) {
  PPP_REQUIRE_SHARED_DATA();
  const NavData nav = readRinexNav(esbcNav());
  ASSERT_GT(nav.gps.size(), 200u);
  ASSERT_GT(nav.galileo.size(), 1500u);
  const GnssTime day = test::gpst(2020, 6, 25, 12);
  std::vector<std::vector<std::uint8_t>> payloads;
  std::map<int, int> types;
  for (const auto& e : nav.gps) {
    payloads.push_back(encodeEphemerisPayload(e));
    ++types[ephemerisMessageType(e)];
  }
  for (const auto& e : nav.galileo) {
    payloads.push_back(encodeEphemerisPayload(e));
    ++types[ephemerisMessageType(e)];
  }
  StreamCounters counters;
  const Rtcm3Output out = decodeFrames(payloads, day, &counters);
  EXPECT_EQ(counters.totalProblems(), 0u);
  ASSERT_EQ(out.gps.size(), nav.gps.size());
  ASSERT_EQ(out.galileo.size(), nav.galileo.size());

  Worst worst;
  std::map<std::string, int> by_design;
  for (std::size_t i = 0; i < nav.gps.size(); ++i) {
    const GpsLnavEphemeris& a = nav.gps[i];
    const GpsLnavEphemeris& b = out.gps[i];
    const std::string id = a.satellite.toString() + " " + a.orbit.toe.toString();
    ASSERT_EQ(a.satellite, b.satellite) << id;
    EXPECT_EQ(a.iode, b.iode) << id;
    EXPECT_EQ(a.iodc, b.iodc) << id;
    EXPECT_EQ(a.week, b.week) << id;
    EXPECT_EQ(a.health, b.health) << id;
    EXPECT_EQ(a.codes_on_l2, b.codes_on_l2) << id;
    EXPECT_EQ(a.l2p_data_flag, b.l2p_data_flag) << id;
    EXPECT_EQ(a.clock.toc, b.clock.toc) << id;
    addKepler(worst, a.orbit, b.orbit, id);
    worst.add(a.clock.af0_s, b.clock.af0_s, p2(-31), id + " af0");
    worst.add(a.clock.af1_sps, b.clock.af1_sps, p2(-43), id + " af1");
    worst.add(a.clock.af2_sps2, b.clock.af2_sps2, p2(-55), id + " af2");
    worst.add(a.tgd_s, b.tgd_s, p2(-31), id + " TGD");
    // URA: the index of the smallest table value not below it.
    EXPECT_GE(b.ura_m, a.ura_m) << id;
    if (b.ura_m != a.ura_m) ++by_design["GPS URA as its index's table value"];
    EXPECT_EQ(a.fit_interval_h > 4.0, b.fit_interval_h > 4.0) << id;
    if (b.fit_interval_h != a.fit_interval_h) ++by_design["GPS fit interval as a flag"];
    if (a.transmission_sow) ++by_design["transmission time (no field)"];
  }
  for (std::size_t i = 0; i < nav.galileo.size(); ++i) {
    const GalileoEphemeris& a = nav.galileo[i];
    const GalileoEphemeris& b = out.galileo[i];
    const std::string id = a.satellite.toString() + " " + a.orbit.toe.toString();
    ASSERT_EQ(a.satellite, b.satellite) << id;
    EXPECT_EQ(a.type, b.type) << id;
    EXPECT_EQ(a.iod_nav, b.iod_nav) << id;
    EXPECT_EQ(a.week, b.week) << id;
    EXPECT_EQ(a.health, b.health) << id;
    EXPECT_EQ(a.clock.toc, b.clock.toc) << id;
    addKepler(worst, a.orbit, b.orbit, id);
    worst.add(a.clock.af0_s, b.clock.af0_s, p2(-34), id + " af0");
    worst.add(a.clock.af1_sps, b.clock.af1_sps, p2(-46), id + " af1");
    worst.add(a.clock.af2_sps2, b.clock.af2_sps2, p2(-59), id + " af2");
    worst.add(a.bgd_e5a_e1_s, b.bgd_e5a_e1_s, p2(-32), id + " BGD E5a");
    if (a.type == GalileoNavType::INav) {
      ASSERT_TRUE(a.bgd_e5b_e1_s && b.bgd_e5b_e1_s) << id;
      worst.add(*a.bgd_e5b_e1_s, *b.bgd_e5b_e1_s, p2(-32), id + " BGD E5b");
    }
    ASSERT_EQ(a.sisa_m.has_value(), b.sisa_m.has_value()) << id;
    if (a.sisa_m) worst.add(*a.sisa_m, *b.sisa_m, 0.01, id + " SISA");
    if (a.data_sources != b.data_sources) ++by_design["Galileo data sources fixed per message type"];
    if (a.transmission_sow) ++by_design["transmission time (no field)"];
  }
  std::printf("[ figures  ] %zu GPS (1019) + %d F/NAV (1045) + %d I/NAV (1046) records; largest difference %.3g "
              "field steps (%s)\n",
              nav.gps.size(), types[1045], types[1046], worst.steps, worst.where.c_str());
  for (const auto& [what, n] : by_design) std::printf("[ by design] %s: %d\n", what.c_str(), n);
  EXPECT_GT(types[1045], 100);
  EXPECT_GT(types[1046], 100);
  EXPECT_LE(worst.steps, 0.5) << worst.where;
  // Re-encoding the decoded records gives the same bytes: nothing is lost twice.
  for (std::size_t i = 0; i < nav.gps.size(); ++i) EXPECT_EQ(encodeEphemerisPayload(out.gps[i]), payloads[i]);
  for (std::size_t i = 0; i < nav.galileo.size(); ++i)
    EXPECT_EQ(encodeEphemerisPayload(out.galileo[i]), payloads[nav.gps.size() + i]);
}

/// The GLONASS records of a real recording (decoded by us).
std::vector<GlonassEphemeris> recordingGlonass(const std::string& name, const GnssTime& reference) {
  const std::string bytes = test::readFileBytes(test::dataPath("streams/rtcm/" + name));
  Rtcm3DecoderOptions options;
  options.reference_time = reference;
  Rtcm3Decoder decoder(options);
  decoder.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  decoder.finish();
  return decoder.output().glonass;
}

TEST(Rtcm3EphemerisEncoder, GlonassRecordsOfRealRecordingsRoundTripExactly) {
  PPP_REQUIRE_SHARED_DATA();
  std::size_t compared = 0;
  for (const auto& [name, reference] : {std::make_pair(std::string("week-rollover-STR24.rtcm3"),
                                                       test::gpst(2018, 7, 14, 23, 55)),
                                        std::make_pair(std::string("gmsd7_20121014.rtcm3"), test::gpst(2012, 10, 14))}) {
    const auto records = recordingGlonass(name, reference);
    ASSERT_GT(records.size(), 5u) << name;
    std::vector<std::vector<std::uint8_t>> payloads;
    for (const auto& g : records) payloads.push_back(encodeEphemerisPayload(g));
    for (const auto& p : payloads) EXPECT_EQ(p.size(), 45u);  // 360 bits (RTCM 10403.3 table 3.5-12)
    StreamCounters counters;
    const Rtcm3Output out = decodeFrames(payloads, reference, &counters);
    EXPECT_EQ(counters.totalProblems(), 0u) << name;
    ASSERT_EQ(out.glonass.size(), records.size()) << name;
    for (std::size_t i = 0; i < records.size(); ++i) {
      const GlonassEphemeris& a = records[i];
      const GlonassEphemeris& b = out.glonass[i];
      const std::string id = name + " " + a.satellite.toString() + " " + a.tb.toString();
      EXPECT_EQ(a.satellite, b.satellite) << id;
      EXPECT_EQ(a.tb, b.tb) << id;
      EXPECT_EQ(a.frequency_channel, b.frequency_channel) << id;
      EXPECT_EQ(a.health, b.health) << id;
      EXPECT_EQ(a.age_days, b.age_days) << id;
      EXPECT_EQ(a.message_frame_time_s, b.message_frame_time_s) << id;
      EXPECT_EQ(a.minus_tau_n_s, b.minus_tau_n_s) << id;
      EXPECT_EQ(a.gamma_n, b.gamma_n) << id;
      EXPECT_EQ(a.position_m, b.position_m) << id;
      EXPECT_EQ(a.velocity_mps, b.velocity_mps) << id;
      EXPECT_EQ(a.acceleration_mps2, b.acceleration_mps2) << id;
      ++compared;
    }
  }
  std::printf("[ figures  ] %zu GLONASS 1020 records of STR2 and GMSD re-encoded and decoded: equal\n", compared);
}

TEST(Rtcm3EphemerisEncoder, RealRecordingFramesAreReEncodedBitForBit) {
  PPP_REQUIRE_SHARED_DATA();
  // STR2's 1019/1042/1044/1045/1046 frames (a Trimble NetR9, 2018): each decoded,
  // then encoded again, must give the receiver's own payload bit for bit (these
  // messages have no field our records leave out, the reserved bits being zero),
  // but for the week field of records sent in another week than their toe's.
  // 1020 carries fields no record keeps (almanac health, P1-P4, NT, tauC, ...): its
  // round trip is the field test above.
  const std::string bytes = test::readFileBytes(test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3"));
  Rtcm3DecoderOptions options;
  options.reference_time = test::gpst(2018, 7, 14, 23, 55);
  Rtcm3Decoder decoder(options);
  std::map<int, std::size_t> equal, unequal, week_of_transmission;
  Rtcm3Framer framer;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), [&](const Rtcm3Frame& f) {
    const int t = f.message_type;
    if (t != 1019 && t != 1042 && t != 1044 && t != 1045 && t != 1046) return;
    decoder.output().clear();
    decoder.decodeFrame(f);
    const Rtcm3Output& out = decoder.output();
    std::vector<std::uint8_t> again;
    if (!out.gps.empty()) again = encodeEphemerisPayload(out.gps.front());
    else if (!out.galileo.empty()) again = encodeEphemerisPayload(out.galileo.front());
    else if (!out.beidou.empty()) again = encodeEphemerisPayload(out.beidou.front());
    // The week field (DF076 / DF289 / DF489): the receiver writes the week of
    // transmission, we the week of toe (as RTKLIB reads it: rtcm3.c decode_type1019,
    // gpst2time(week, toes)); they differ by one for a record sent in another week
    // than its toe's (GPS: sent on Saturday for a Sunday toe; Galileo: a Saturday toe
    // still sent after midnight), which this recording, across a week boundary, holds.
    // Plain variables, not structured bindings: the lambdas below capture them, which
    // C++17 (and clang before 16) does not allow for a binding.
    const std::pair<int, int> week_field = t == 1044 ? std::make_pair(446, 10)
                                         : t == 1019 ? std::make_pair(18, 10)
                                         : t == 1042 ? std::make_pair(18, 13)
                                                     : std::make_pair(18, 12);
    const int week_at = week_field.first, week_bits = week_field.second;
    auto field = [](const std::vector<std::uint8_t>& v, int at, int n) {
      std::int64_t x = 0;
      for (int i = at; i < at + n; ++i) x = (x << 1) | ((v[i / 8] >> (7 - i % 8)) & 1);
      return x;
    };
    auto masked = [&](std::vector<std::uint8_t> v) {
      for (int i = week_at; i < week_at + week_bits; ++i) v[i / 8] &= static_cast<std::uint8_t>(~(0x80u >> (i % 8)));
      return v;
    };
    if (again == f.payload) {
      ++equal[t];
    } else if (again.size() == f.payload.size() && masked(again) == masked(f.payload) &&
               std::abs(field(again, week_at, week_bits) - field(f.payload, week_at, week_bits)) == 1) {
      ++week_of_transmission[t];
    } else {
      ++unequal[t];
      std::string bits;  // the payload bits that differ
      for (std::size_t i = 0; i < std::max(again.size(), f.payload.size()) * 8; ++i) {
        const auto bit = [i](const std::vector<std::uint8_t>& v) { return i / 8 < v.size() ? (v[i / 8] >> (7 - i % 8)) & 1 : 2; };
        if (bit(again) != bit(f.payload)) bits += " " + std::to_string(i);
      }
      ADD_FAILURE() << "type " << t << " frame " << f.frame_index << " differs after decoding and encoding at bits"
                    << bits.substr(0, 120) << " (sizes " << again.size() << ", " << f.payload.size() << ")";
    }
  });
  std::string figures;
  for (const auto& [t, n] : equal) figures += " " + std::to_string(t) + ":" + std::to_string(n);
  std::string weeks;
  for (const auto& [t, n] : week_of_transmission) weeks += " " + std::to_string(t) + ":" + std::to_string(n);
  std::printf("[ figures  ] STR2 ephemeris frames re-encoded bit for bit:%s; equal but the week field (week of "
              "transmission, ours of toe, one apart):%s\n", figures.c_str(), weeks.c_str());
  for (const int t : {1042, 1045, 1046}) EXPECT_GT(equal[t], 0u) << t;
  for (const int t : {1019, 1045}) EXPECT_GT(equal[t] + week_of_transmission[t], 10u) << t;
  EXPECT_TRUE(unequal.empty());
}

TEST(Rtcm3EphemerisEncoder, FieldIndexTables) {
  // IS-GPS-200 20.3.3.3.1.3: N=0 covers up to 2.4 m, N=1 up to 3.4 m, ..., 15 beyond 6144 m.
  EXPECT_EQ(gpsUraIndex(2.0), 0);
  EXPECT_EQ(gpsUraIndex(2.4), 0);
  EXPECT_EQ(gpsUraIndex(2.5), 1);
  EXPECT_EQ(gpsUraIndex(1e5), 15);
  // Galileo OS SIS ICD 5.1.12: 0.01 m steps to 0.49, 0.02 to 0.98, 0.04 to 1.96, 0.16 to 6 m.
  EXPECT_EQ(galileoSisaIndex(0.31), 31);
  EXPECT_EQ(galileoSisaIndex(0.6), 55);
  EXPECT_EQ(galileoSisaIndex(1.2), 80);
  EXPECT_EQ(galileoSisaIndex(3.12), 107);
  EXPECT_EQ(galileoSisaIndex(std::nullopt), 255);
  GlonassEphemeris g;
  g.satellite = SatelliteId{GnssSystem::GPS, 3};
  EXPECT_THROW(encodeEphemerisPayload(g), std::invalid_argument);
  GpsLnavEphemeris e;
  e.satellite = SatelliteId{GnssSystem::GPS, 5};
  e.orbit.crs_m = 5000.0;  // beyond the 16-bit field (+-1024 m)
  EXPECT_THROW(encodeEphemerisPayload(e), std::out_of_range);
}

// ---- Peer: RTKLIB convbin on the encoded stream --------------------------------

/// Runs `convbin -r rtcm3 -tr DATE -ro -EPHALL` (every record, also those with a known
/// IOD) on `stream` and reads its navigation file.
NavData convbinNav(const fs::path& stream, const std::string& ref_date, const fs::path& dir) {
  const fs::path nav = dir / "peer.nav", obs = dir / "peer.obs";
  const std::string cmd = "convbin -r rtcm3 -tr " + ref_date + " -ro -EPHALL -o '" + obs.string() + "' -n '" +
                          nav.string() + "' '" + stream.string() + "' > '" + (dir / "convbin.log").string() + "' 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return readRinexNav(nav.string());
}

void writeFrames(const fs::path& path, const std::vector<std::vector<std::uint8_t>>& payloads) {
  std::ofstream out(path, std::ios::binary);
  for (const auto& p : payloads) {
    const auto f = encodeRtcm3Frame(p);
    out.write(reinterpret_cast<const char*>(f.data()), static_cast<std::streamsize>(f.size()));
  }
}

/// |a - b| within the 12 printed significant digits of RINEX (%19.12E).
bool printedEqual(double a, double b) { return std::abs(a - b) <= 1e-11 * std::max(std::abs(a), std::abs(b)) + 1e-300; }

TEST(Rtcm3EphemerisEncoder, ConvbinReadsTheEncodedEsbcRecordsAsTheSourceFile) {
  PPP_REQUIRE_SHARED_DATA();
  if (!haveConvbin()) GTEST_SKIP() << "RTKLIB convbin not installed (Debian package rtklib)";
  const NavData nav = readRinexNav(esbcNav());
  const fs::path dir = test::tempDir("eph_encoder_peer");
  std::vector<std::vector<std::uint8_t>> payloads;
  for (const auto& e : nav.gps) payloads.push_back(encodeEphemerisPayload(e));
  for (const auto& e : nav.galileo) payloads.push_back(encodeEphemerisPayload(e));
  writeFrames(dir / "esbc_eph.rtcm3", payloads);
  const NavData peer = convbinNav(dir / "esbc_eph.rtcm3", "2020/06/25 00:00:00", dir);

  std::size_t gps_matched = 0, gal_matched = 0, fields = 0, unequal = 0;
  std::map<std::string, int> by_design;
  auto check = [&](double a, double b, const std::string& what) {
    ++fields;
    if (!printedEqual(a, b)) {
      ++unequal;
      ADD_FAILURE() << what << ": source " << a << ", convbin " << b;
    }
  };
  auto kepler = [&](const KeplerOrbit& a, const KeplerOrbit& b, const std::string& id) {
    check(a.crs_m, b.crs_m, id + " crs");
    check(a.delta_n_radps, b.delta_n_radps, id + " dn");
    check(a.m0_rad, b.m0_rad, id + " M0");
    check(a.cuc_rad, b.cuc_rad, id + " cuc");
    check(a.eccentricity, b.eccentricity, id + " e");
    check(a.cus_rad, b.cus_rad, id + " cus");
    check(a.sqrt_a_sqrtm, b.sqrt_a_sqrtm, id + " sqrtA");
    check(a.toe_sow, b.toe_sow, id + " toe");
    check(a.cic_rad, b.cic_rad, id + " cic");
    check(a.omega0_rad, b.omega0_rad, id + " Omega0");
    check(a.cis_rad, b.cis_rad, id + " cis");
    check(a.i0_rad, b.i0_rad, id + " i0");
    check(a.crc_m, b.crc_m, id + " crc");
    check(a.omega_rad, b.omega_rad, id + " omega");
    check(a.omega_dot_radps, b.omega_dot_radps, id + " Omega dot");
    check(a.idot_radps, b.idot_radps, id + " IDOT");
  };
  for (const auto& a : nav.gps) {
    const GpsLnavEphemeris* b = nullptr;
    for (const auto& p : peer.gps)
      if (p.satellite == a.satellite && p.orbit.toe == a.orbit.toe && p.iode == a.iode) b = &p;
    if (!b) {
      ADD_FAILURE() << "convbin has no record of " << a.satellite.toString() << " toe " << a.orbit.toe.toString();
      continue;
    }
    const std::string id = a.satellite.toString() + " " + a.orbit.toe.toString();
    ++gps_matched;
    EXPECT_EQ(a.clock.toc, b->clock.toc) << id;
    EXPECT_EQ(a.iodc, b->iodc) << id;
    EXPECT_EQ(a.week, b->week) << id;
    EXPECT_EQ(a.health, b->health) << id;
    check(a.clock.af0_s, b->clock.af0_s, id + " af0");
    check(a.clock.af1_sps, b->clock.af1_sps, id + " af1");
    check(a.clock.af2_sps2, b->clock.af2_sps2, id + " af2");
    check(a.tgd_s, b->tgd_s, id + " TGD");
    kepler(a.orbit, b->orbit, id);
    if (a.ura_m != b->ura_m) ++by_design["GPS URA as its index's table value"];
    if (a.fit_interval_h != b->fit_interval_h) ++by_design["GPS fit interval as a flag"];
    if (a.transmission_sow != b->transmission_sow) ++by_design["transmission time: convbin's stream time"];
  }
  for (const auto& a : nav.galileo) {
    const GalileoEphemeris* b = nullptr;
    for (const auto& p : peer.galileo)
      if (p.satellite == a.satellite && p.orbit.toe == a.orbit.toe && p.iod_nav == a.iod_nav && p.type == a.type &&
          printedEqual(p.clock.af0_s, a.clock.af0_s))
        b = &p;
    if (!b) {
      ++by_design["Galileo record absent from convbin's file"];
      continue;
    }
    const std::string id = a.satellite.toString() + " " + a.orbit.toe.toString();
    ++gal_matched;
    EXPECT_EQ(a.clock.toc, b->clock.toc) << id;
    EXPECT_EQ(a.week, b->week) << id;
    EXPECT_EQ(a.health, b->health) << id;
    check(a.clock.af1_sps, b->clock.af1_sps, id + " af1");
    check(a.clock.af2_sps2, b->clock.af2_sps2, id + " af2");
    check(a.bgd_e5a_e1_s, b->bgd_e5a_e1_s, id + " BGD E5a");
    if (a.bgd_e5b_e1_s && b->bgd_e5b_e1_s) check(*a.bgd_e5b_e1_s, *b->bgd_e5b_e1_s, id + " BGD E5b");
    kepler(a.orbit, b->orbit, id);
    if (a.sisa_m && b->sisa_m) check(*a.sisa_m, *b->sisa_m, id + " SISA");
    if (a.data_sources != b->data_sources) ++by_design["Galileo data sources as convbin writes them"];
    if (a.transmission_sow != b->transmission_sow) ++by_design["transmission time: convbin's stream time"];
  }
  std::printf("[ figures  ] convbin on the encoded ESBC records: %zu/%zu GPS and %zu/%zu Galileo records found, %zu "
              "fields compared, %zu unequal at the printed precision\n",
              gps_matched, nav.gps.size(), gal_matched, nav.galileo.size(), fields, unequal);
  for (const auto& [what, n] : by_design) std::printf("[ by design] %s: %d\n", what.c_str(), n);
  EXPECT_EQ(gps_matched, nav.gps.size());
  EXPECT_GT(gal_matched, nav.galileo.size() * 9 / 10);
  EXPECT_EQ(unequal, 0u);
}

TEST(Rtcm3EphemerisEncoder, ConvbinReadsOurGlonassRecordsAsTheOriginalRecording) {
  PPP_REQUIRE_SHARED_DATA();
  if (!haveConvbin()) GTEST_SKIP() << "RTKLIB convbin not installed (Debian package rtklib)";
  // STR2's GLONASS records re-encoded by us, and the original recording, both through convbin.
  const auto records = recordingGlonass("week-rollover-STR24.rtcm3", test::gpst(2018, 7, 14, 23, 55));
  ASSERT_GT(records.size(), 5u);
  const fs::path dir = test::tempDir("eph_encoder_glonass_peer");
  std::vector<std::vector<std::uint8_t>> payloads;
  for (const auto& g : records) payloads.push_back(encodeEphemerisPayload(g));
  writeFrames(dir / "glonass.rtcm3", payloads);
  fs::create_directories(dir / "ours");
  fs::create_directories(dir / "original");
  const NavData ours = convbinNav(dir / "glonass.rtcm3", "2018/07/14 23:55:00", dir / "ours");
  const NavData original =
      convbinNav(test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3"), "2018/07/14 23:55:00", dir / "original");
  ASSERT_FALSE(original.glonass.empty());
  std::size_t matched = 0;
  for (const auto& a : original.glonass) {
    const GlonassEphemeris* b = nullptr;
    for (const auto& p : ours.glonass)
      if (p.satellite == a.satellite && p.tb == a.tb && printedEqual(p.message_frame_time_s, a.message_frame_time_s))
        b = &p;
    ASSERT_TRUE(b) << "no record of " << a.satellite.toString() << " tb " << a.tb.toString() << " from our stream";
    const std::string id = a.satellite.toString() + " " + a.tb.toString();
    ++matched;
    EXPECT_EQ(a.frequency_channel, b->frequency_channel) << id;
    EXPECT_EQ(a.health, b->health) << id;
    EXPECT_EQ(a.age_days, b->age_days) << id;
    EXPECT_TRUE(printedEqual(a.minus_tau_n_s, b->minus_tau_n_s)) << id;
    EXPECT_TRUE(printedEqual(a.gamma_n, b->gamma_n)) << id;
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(printedEqual(a.position_m[k], b->position_m[k])) << id << " axis " << k;
      EXPECT_TRUE(printedEqual(a.velocity_mps[k], b->velocity_mps[k])) << id << " axis " << k;
      EXPECT_TRUE(printedEqual(a.acceleration_mps2[k], b->acceleration_mps2[k])) << id << " axis " << k;
    }
  }
  std::printf("[ figures  ] convbin: %zu GLONASS records of STR2's own 1020 equal those of our re-encoded 1020\n",
              matched);
  EXPECT_EQ(matched, original.glonass.size());
}

}  // namespace
}  // namespace ppp
