// UBX RXM-SFRBX GLONASS strings and BeiDou D1/D2 subframes into ephemerides.
//
// No shared UBX recording carries them (gnss_1730.ubx: GPS and Galileo
// navigation data only), so the proof is built on real broadcast values: the
// BeiDou records of the ESBC day (esbc-2020-177, ESBC00DNK_R_20201770000_01D_MN.rnx,
// 06:00-08:00; GEO C05 among them; the file has no GLONASS records) and the
// GLONASS records (RTCM 1020) of the recording week-rollover-STR24.rtcm3
// (2018-07-14/15, decoded by our RTCM decoder, itself equal to convbin) are encoded
// into SFRBX frames as a u-blox receiver delivers them (io/ubx/ubx_nav_encoder.h:
// GLONASS strings 1-5 with the Hamming code of GLONASS ICD 5.1 4.7; BeiDou D1
// subframes 1-3 and D2 pages 1-10 with the BCH(15,11) parity of
// BDS-SIS-ICD-B1I 5.1.3), preceded by RXM-RAWX frames that give the time.
// The same .ubx file is then decoded by our ppp_stream_convert path and by
// RTKLIB convbin 2.4.3 b34 (Debian rtklib, run here), whose own decoder reads
// the bits with its own field table (rcvraw.c decode_glostr, decode_bds_d1/d2):
// every field of every GLONASS and BeiDou record must agree to the printed
// precision, and states computed from our records must equal those of the
// original file to 1 mm / 0.01 ns.
//
// By design (named): convbin does not check BeiDou parity at all and accepts a
// GLONASS string with the ICD's single-check-bit error; ours counts a failed
// BCH / Hamming check as a checksum error and drops the part (tested below).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "ppp_bayes_tree/app/stream_convert.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/ubx/ubx_decoder.h"
#include "ppp_bayes_tree/io/ubx/ubx_nav_encoder.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "rinex_nav_fields.h"
#include "test_support.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;
using test::gpst;

std::string esbcNav() { return test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_MN.rnx"); }

const NavData& esbc() {
  static const NavData nav = readRinexNav(esbcNav());
  return nav;
}

std::string str24() { return test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3"); }

/// GLONASS records of the STR24 recording, one per (satellite, tb).
const std::vector<GlonassEphemeris>& str24Glonass() {
  static const std::vector<GlonassEphemeris> records = [] {
    Rtcm3DecoderOptions options;
    options.reference_time = gpst(2018, 7, 14, 23, 50, 0);
    RtcmObservationSource source(str24(), options);
    std::vector<GlonassEphemeris> out;
    for (const auto& e : source.scanNavigation().glonass) {
      bool seen = false;
      for (const auto& o : out) seen = seen || (o.satellite == e.satellite && o.tb == e.tb);
      if (!seen) out.push_back(e);
    }
    return out;
  }();
  return records;
}

/// The BeiDou records of 06:00-08:00 GPST and the STR24 GLONASS records encoded as SFRBX, each 5 min before its
/// reference time, in time order, each group after an RXM-RAWX of its time.
struct Synthesized {
  std::vector<std::uint8_t> bytes;
  std::vector<GlonassEphemeris> glonass;
  std::vector<BeidouEphemeris> beidou;
};

Synthesized synthesize() {
  Synthesized out;
  const GnssTime from = gpst(2020, 6, 25, 6, 0, 0), to = gpst(2020, 6, 25, 8, 0, 0);
  std::multimap<GnssTime, std::vector<std::uint8_t>> frames;  // emission time -> frame bytes
  std::uint16_t frame_id = 1;
  for (const auto& e : str24Glonass()) {
    out.glonass.push_back(e);
    for (auto& f : encodeGlonassSfrbx(e, frame_id++)) frames.emplace(e.tb - 300.0, f);
  }
  for (const auto& e : esbc().beidou) {
    if (e.orbit.toe < from || e.orbit.toe > to) continue;
    out.beidou.push_back(e);
    const GnssTime emission = e.orbit.toe - 300.0;
    const double sow = (emission - kGpstMinusBdt_s).gpsWeek().seconds_of_week;
    for (auto& f : encodeBeidouSfrbx(e, static_cast<std::uint32_t>(std::lround(sow)))) frames.emplace(emission, f);
  }
  std::optional<GnssTime> last;
  for (const auto& [t, f] : frames) {
    if (!last || t > *last) {
      const auto rawx = encodeRawxTime(t);
      out.bytes.insert(out.bytes.end(), rawx.begin(), rawx.end());
      last = t;
    }
    out.bytes.insert(out.bytes.end(), f.begin(), f.end());
  }
  return out;
}

#define REQUIRE_ESBC_NAV()                                                                      \
  if (!fs::exists(esbcNav())) GTEST_SKIP() << "ESBC navigation file absent: " << esbcNav();   \
  if (!fs::exists(str24())) GTEST_SKIP() << "RTCM recording absent: " << str24()

struct Decoded {
  std::vector<GlonassEphemeris> glonass;
  std::vector<BeidouEphemeris> beidou;
  StreamCounters counters;
};

Decoded decode(const std::vector<std::uint8_t>& bytes) {
  Decoded d;
  UbxDecoder decoder;
  UbxDecoder::Handlers h;
  h.on_glonass = [&](const GlonassEphemeris& e) { d.glonass.push_back(e); };
  h.on_beidou = [&](const BeidouEphemeris& e) { d.beidou.push_back(e); };
  decoder.feed(bytes.data(), bytes.size(), h);
  decoder.finish();
  d.counters = decoder.counters();
  return d;
}

TEST(UbxSfrbxGlonassBeidou, RealRecordsSurviveTheRoundTrip) {
  REQUIRE_ESBC_NAV();
  const Synthesized s = synthesize();
  ASSERT_GE(s.glonass.size(), 20u);
  ASSERT_GE(s.beidou.size(), 20u);
  const Decoded d = decode(s.bytes);
  EXPECT_EQ(d.counters.totalProblems(), 0u);
  // GLONASS: one record per (satellite, tb) of the file (repeats in the file share tb).
  std::map<std::pair<SatelliteId, GnssTime>, const GlonassEphemeris*> glo;
  for (const auto& e : s.glonass) glo[{e.satellite, e.tb}] = &e;
  EXPECT_EQ(d.glonass.size(), glo.size());
  double worst_m = 0.0, worst_ns = 0.0;
  for (const auto& e : d.glonass) {
    const auto it = glo.find({e.satellite, e.tb});
    ASSERT_NE(it, glo.end()) << e.satellite.toString() << " tb " << e.tb.toString();
    EXPECT_EQ(e.frequency_channel, it->second->frequency_channel);
    for (double dt : {-900.0, 0.0, 900.0}) {
      const BroadcastState a = satelliteState(e, e.tb + dt), b = satelliteState(*it->second, e.tb + dt);
      worst_m = std::fmax(worst_m, (a.position_ecef_m - b.position_ecef_m).norm());
      worst_ns = std::fmax(worst_ns, std::fabs(a.clock_bias_s - b.clock_bias_s) * 1e9);
    }
  }
  std::map<std::tuple<SatelliteId, GnssTime, int>, const BeidouEphemeris*> bds;
  for (const auto& e : s.beidou) bds[{e.satellite, e.orbit.toe, e.aode}] = &e;
  EXPECT_EQ(d.beidou.size(), bds.size());
  int geo = 0;
  for (const auto& e : d.beidou) {
    const auto it = bds.find({e.satellite, e.orbit.toe, e.aode});
    ASSERT_NE(it, bds.end()) << e.satellite.toString() << " toe " << e.orbit.toe.toString();
    EXPECT_EQ(e.clock.toc, it->second->clock.toc);
    EXPECT_EQ(e.bdt_week, it->second->bdt_week);
    EXPECT_EQ(e.health, it->second->health);
    EXPECT_EQ(e.aodc, it->second->aodc);
    geo += e.isGeo();
    for (double dt : {-3600.0, 0.0, 3600.0}) {
      const BroadcastState a = satelliteState(e, e.orbit.toe + dt), b = satelliteState(*it->second, e.orbit.toe + dt);
      worst_m = std::fmax(worst_m, (a.position_ecef_m - b.position_ecef_m).norm());
      worst_ns = std::fmax(worst_ns, std::fabs(a.clock_bias_s - b.clock_bias_s) * 1e9);
    }
  }
  std::printf("SFRBX round trip of ESBC records: %zu GLONASS, %zu BeiDou (%d GEO); max %.6f m, %.6f ns\n",
              d.glonass.size(), d.beidou.size(), geo, worst_m, worst_ns);
  EXPECT_GE(geo, 2);
  EXPECT_LT(worst_m, 1e-3);
  EXPECT_LT(worst_ns, 0.01);
}

TEST(UbxSfrbxGlonassBeidou, ConvbinDecodesTheSameRecords) {
  REQUIRE_ESBC_NAV();
  if (std::system("command -v convbin > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "RTKLIB convbin not installed (Debian package rtklib)";
  const Synthesized s = synthesize();
  const fs::path dir = test::tempDir("sfrbx_glo_bds");
  const fs::path ubx = dir / "esbc_sfrbx.ubx";
  {
    std::ofstream f(ubx, std::ios::binary);
    f.write(reinterpret_cast<const char*>(s.bytes.data()), static_cast<std::streamsize>(s.bytes.size()));
  }
  const fs::path peer_obs = dir / "peer.obs", peer_nav = dir / "peer.nav";
  const std::string cmd = "convbin -r ubx -od -os -o '" + peer_obs.string() + "' -n '" + peer_nav.string() + "' '" +
                          ubx.string() + "' > '" + (dir / "convbin.log").string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const fs::path our_obs = dir / "ours.obs", our_nav = dir / "ours.nav";
  const StreamConversion conv = convertStreamToRinex(ubx.string(), our_obs.string(), our_nav.string(), Rtcm3DecoderOptions{});
  // The RXM-RAWX frames only carry the time of the navigation frames after them: one per
  // emission time, 30 min to two years apart (STR24 2018 GLONASS, ESBC 2020 BeiDou). As
  // observation epochs, the screen of receiver epoch times (io/epoch_time_screen.h) rightly
  // refuses them (4 isolated jumps after the first); the navigation frames must all decode.
  EXPECT_EQ(conv.counters.totalProblems() - conv.counters.count(StreamProblemKind::EpochTimeRefused), 0u)
      << conv.counters.problemLines();
  EXPECT_EQ(conv.counters.count(StreamProblemKind::EpochTimeRefused), 4u) << conv.counters.problemLines();
  const auto peer = test::readRawNavRecords(peer_nav.string(), "RC");
  const auto ours = test::readRawNavRecords(our_nav.string(), "RC");
  std::size_t glonass = 0, beidou = 0, fields = 0;
  std::vector<std::string> failures;
  for (const auto& p : peer) {
    const test::RawNavRecord* o = nullptr;
    for (const auto& e : ours)
      if (e.satellite == p.satellite && e.epoch == p.epoch) o = &e;
    if (!o) {
      failures.push_back(p.satellite + " " + p.epoch + ": no record of ours");
      continue;
    }
    (p.satellite[0] == 'R' ? glonass : beidou)++;
    ASSERT_EQ(o->fields.size(), p.fields.size()) << p.satellite << " " << p.epoch;
    for (std::size_t k = 0; k < p.fields.size(); ++k) {
      if (p.satellite[0] == 'C' && (k == 20 || k == 22 || k >= 29)) continue;  // spare fields
      if (p.satellite[0] == 'R' && k >= 15) continue;
      ++fields;
      const auto& a = p.fields[k];
      const auto& b = o->fields[k];
      if (!a && !b) continue;
      if (!a || !b || !test::agreesToPrintedPrecision(*a, p.text[k], *b, o->text[k]))
        failures.push_back(p.satellite + " " + p.epoch + " field " + std::to_string(k) + ": peer '" + p.text[k] +
                           "', ours '" + o->text[k] + "'");
    }
  }
  std::printf("SFRBX GLONASS/BeiDou vs convbin: %zu GLONASS and %zu BeiDou records (peer), %zu ours, %zu fields\n",
              glonass, beidou, ours.size(), fields);
  for (const auto& f : failures) std::printf("  FAIL %s\n", f.c_str());
  EXPECT_TRUE(failures.empty());
  EXPECT_EQ(peer.size(), ours.size());
  EXPECT_GE(glonass, 20u);
  EXPECT_GE(beidou, 20u);
}

TEST(UbxSfrbxGlonassBeidou, BadParityAndHammingAreCountedAndTheRecordRejected) {
  REQUIRE_ESBC_NAV();
  ASSERT_FALSE(str24Glonass().empty());
  const GlonassEphemeris& r = str24Glonass().front();
  const BeidouEphemeris* meo = nullptr;
  const BeidouEphemeris* geo = nullptr;
  for (const auto& e : esbc().beidou) {
    if (!meo && !e.isGeo()) meo = &e;
    if (!geo && e.isGeo()) geo = &e;
  }
  ASSERT_TRUE(meo && geo);
  // A payload bit of word `word` of frame `frame` flipped (payload offset 8 + 4 word; checksum redone).
  auto flip = [](std::vector<std::uint8_t> f, int word, int bit) {
    std::vector<std::uint8_t> payload(f.begin() + 6, f.end() - 2);
    payload[static_cast<std::size_t>(8 + 4 * word + bit / 8)] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    return encodeUbxFrame(0x02, 0x13, payload);
  };
  auto stream = [](const GnssTime& t, const std::vector<UbxFrameBytes>& frames) {
    std::vector<std::uint8_t> bytes = encodeRawxTime(t);
    for (const auto& f : frames) bytes.insert(bytes.end(), f.begin(), f.end());
    return bytes;
  };
  const auto glo_frames = encodeGlonassSfrbx(r, 7);
  const auto meo_frames = encodeBeidouSfrbx(*meo, 0u + static_cast<std::uint32_t>(std::lround(
      (meo->orbit.toe - 300.0 - kGpstMinusBdt_s).gpsWeek().seconds_of_week)));
  const auto geo_frames = encodeBeidouSfrbx(*geo, 0u + static_cast<std::uint32_t>(std::lround(
      (geo->orbit.toe - 300.0 - kGpstMinusBdt_s).gpsWeek().seconds_of_week)));
  // Intact: one record each.
  EXPECT_EQ(decode(stream(r.tb - 300.0, glo_frames)).glonass.size(), 1u);
  EXPECT_EQ(decode(stream(meo->orbit.toe - 300.0, meo_frames)).beidou.size(), 1u);
  EXPECT_EQ(decode(stream(geo->orbit.toe - 300.0, geo_frames)).beidou.size(), 1u);
  // GLONASS string 2 with a data bit flipped (x-velocity region of word 1).
  auto bad_glo = glo_frames;
  bad_glo[1] = flip(bad_glo[1], 1, 5);
  Decoded d = decode(stream(r.tb - 300.0, bad_glo));
  EXPECT_TRUE(d.glonass.empty());
  EXPECT_EQ(d.counters.count(StreamProblemKind::ChecksumError), 1u);
  ASSERT_FALSE(d.counters.problems.empty());
  EXPECT_NE(d.counters.problems.front().describe().find("Hamming"), std::string::npos)
      << d.counters.problems.front().describe();
  // Two bits flipped in one GLONASS string: detected as well (c_sigma = 0, some c_k = 1).
  bad_glo = glo_frames;
  bad_glo[0] = flip(flip(bad_glo[0], 0, 3), 1, 20);
  d = decode(stream(r.tb - 300.0, bad_glo));
  EXPECT_TRUE(d.glonass.empty());
  EXPECT_EQ(d.counters.count(StreamProblemKind::ChecksumError), 1u);
  // BeiDou D1 subframe 2, word 5 data bit: BCH parity fails, no record.
  auto bad_meo = meo_frames;
  bad_meo[1] = flip(bad_meo[1], 4, 10);
  d = decode(stream(meo->orbit.toe - 300.0, bad_meo));
  EXPECT_TRUE(d.beidou.empty());
  EXPECT_EQ(d.counters.count(StreamProblemKind::ChecksumError), 1u);
  // BeiDou D2 page 7 (toe, i0), word 3: no record.
  auto bad_geo = geo_frames;
  bad_geo[6] = flip(bad_geo[6], 2, 17);
  d = decode(stream(geo->orbit.toe - 300.0, bad_geo));
  EXPECT_TRUE(d.beidou.empty());
  EXPECT_EQ(d.counters.count(StreamProblemKind::ChecksumError), 1u);
  // A GLONASS string 4 naming another slot: inconsistent, counted, no record.
  GlonassEphemeris other = r;
  other.satellite.prn = r.satellite.prn == 1 ? 2 : 1;
  auto mixed = glo_frames;
  mixed[3] = encodeGlonassSfrbx(other, 7)[3];
  std::vector<std::uint8_t> payload(mixed[3].begin() + 6, mixed[3].end() - 2);
  payload[1] = static_cast<std::uint8_t>(r.satellite.prn);  // delivered on r's svId
  mixed[3] = encodeUbxFrame(0x02, 0x13, payload);
  d = decode(stream(r.tb - 300.0, mixed));
  EXPECT_TRUE(d.glonass.empty());
  EXPECT_EQ(d.counters.count(StreamProblemKind::InconsistentEphemeris), 1u);
}

}  // namespace
}  // namespace ppp
