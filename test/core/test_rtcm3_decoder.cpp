// RTCM 3 decoder: real recordings against RTKLIB convbin (Debian rtklib 2.4.3 b34,
// run here into a temporary directory), round trips through the MSM7 encoder, and
// bad input.
//
// The peer comparison converts each recording with our convert path
// (convertStreamToRinex: RtcmObservationSource + RinexObsWriter + RinexNavWriter)
// and with `convbin -r rtcm3 -od -os -tr DATE`, reads both RINEX files with our
// reader and compares epoch by epoch every observation convbin printed. Where
// convbin differs by design or is wrong, the case is named here and counted:
//  - LLI with the half-cycle flag (DF420 = 1): RTKLIB adds 3 instead of setting
//    bit 1 (rtcm3.c save_msm_obs: lossoflock + (half ? 3 : 0)), so it prints 3
//    (4 with a loss of lock, which reads as the BOC-tracking bit) where RINEX
//    3.04 5.3 wants 2 (3).
//  - Doppler: RTKLIB stores it as float (7 significant digits), so the printed
//    third decimal can differ by one unit; we keep double.
//  - SNR of MSM6/7 (1/16 dB-Hz): RTKLIB rounds half up to its 0.001 dB-Hz unit,
//    printf rounds our exact x.xxx5 value half to even: one unit in the last digit.
//  - GLONASS phase and Doppler before the first 1020 (MSM4 has no channel):
//    convbin leaves them blank; our source knows the channel from its scan of the
//    whole file and gives them.
//  - The first observation of each satellite signal: convbin prints LLI 1 (in the
//    first epoch because convrnx.c convobs flags every phase of a new station, later
//    because its lock memory holds the lock time its scan pass saw at the end of
//    the file); ours says loss of lock only where the lock time says so.
//  - LLI 1 on the first observation after an epoch without the signal: convbin
//    flags it; ours follows the lock-time indicator, which did not drop.
//  - A damaged frame: RTKLIB skips the whole length its header claims, we
//    resynchronise at the next byte and find the frames inside that span.
//  - Signals for which RTKLIB has no observation slot (NFREQ+NEXOBS) are absent
//    from convbin's file; ours has them.
//  - gmsd7_20121014: its BeiDou MSM carry GPST (RTCM 3.2 draft encoder). RTKLIB
//    reads BDT, puts BeiDou 14 s late and, because that time differs from the
//    open epoch, discards the GPS/GLONASS/QZSS cells of every epoch (its output
//    holds BeiDou only). We compare our BeiDou with convbin's 14 s later, and our
//    other systems with convbin run on the same stream without the BeiDou frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "ppp_bayes_tree/app/stream_convert.h"
#include "ppp_bayes_tree/io/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex_obs_reader.h"
#include "ppp_bayes_tree/io/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/rtcm3_msm_encoder.h"
#include "ppp_bayes_tree/io/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/stream_format.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "test_support.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;

std::string rtcmPath(const std::string& name) { return test::dataPath("streams/rtcm/" + name); }

bool haveConvbin() { return std::system("command -v convbin > /dev/null 2>&1") == 0; }

#define REQUIRE_STREAM_AND_CONVBIN(path)                                                     \
  if (!fs::exists(path)) GTEST_SKIP() << "stream recording absent: " << (path);              \
  if (!haveConvbin()) GTEST_SKIP() << "RTKLIB convbin not installed (Debian package rtklib)"

/// Runs convbin; returns false when it failed.
bool runConvbin(const std::string& input, const std::string& ref_date, const fs::path& obs, const fs::path& nav) {
  const std::string cmd = "convbin -r rtcm3 -od -os -tr " + ref_date + " -o '" + obs.string() + "' -n '" +
                          nav.string() + "' '" + input + "' > '" + obs.string() + ".log' 2>&1";
  return std::system(cmd.c_str()) == 0 && fs::exists(obs);
}

/// A copy of `input` without the MSM frames of types [first_type, last_type]. The
/// multiple-message bit (DF393, payload bit 54) of the MSM before each removed one is
/// cleared, so that the epoch still ends where the removed message ended it.
void writeWithoutTypes(const std::string& input, const fs::path& out, int first_type, int last_type) {
  const std::string bytes = test::readFileBytes(input);
  Rtcm3Framer framer;
  std::vector<std::vector<std::uint8_t>> kept;
  std::optional<std::size_t> last_msm;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), [&](const Rtcm3Frame& f) {
    if (f.message_type >= first_type && f.message_type <= last_type) {
      const bool multiple = f.payload.size() > 6 && (f.payload[6] & 0x02);
      if (!multiple && last_msm) kept[*last_msm][6] &= static_cast<std::uint8_t>(~0x02);
      return;
    }
    kept.push_back(f.payload);
    if (msmTypeInfo(f.message_type)) last_msm = kept.size() - 1;
  });
  std::ofstream os(out, std::ios::binary);
  for (const auto& payload : kept) {
    const auto frame = encodeRtcm3Frame(payload);
    os.write(reinterpret_cast<const char*>(frame.data()), static_cast<std::streamsize>(frame.size()));
  }
}

std::vector<ObsEpoch> readAll(const fs::path& path, RinexObsHeader& header) {
  RinexObsReader reader = RinexObsReader::open(path.string());
  header = reader.header();
  std::vector<ObsEpoch> epochs;
  ObsEpoch e;
  while (reader.next(e)) epochs.push_back(e);
  return epochs;
}

struct Comparison {
  std::size_t peer_epochs = 0, matched_epochs = 0, compared = 0, identical = 0;
  std::map<std::string, std::size_t> named;  // named differences by case
  std::vector<std::string> failures;
  void fail(const std::string& text) {
    if (failures.size() < 20) failures.push_back(text);
    else if (failures.size() == 20) failures.push_back("...");
  }
};

/// Compares the peer's observations of the systems accepted by `take` with ours.
/// `peer_shift_s` is added to our epoch time to find the peer's epoch.
void compareObservations(const fs::path& peer_path, const fs::path& ours_path, Comparison& c,
                         const std::function<bool(GnssSystem)>& take, double peer_shift_s = 0.0,
                         std::optional<GnssTime> glonass_lost_by_peer = std::nullopt) {
  RinexObsHeader peer_header, our_header;
  const auto peer = readAll(peer_path, peer_header);
  const auto ours = readAll(ours_path, our_header);
  std::map<std::int64_t, const ObsEpoch*> by_time;
  for (const auto& e : ours) by_time[std::llround((e.time + peer_shift_s).toGpsSecondsDouble() * 1000.0)] = &e;
  std::set<std::int64_t> peer_times;
  const ObsEpoch* first_peer_epoch = nullptr;
  std::set<std::pair<int, std::string>> seen;  // (satellite, code) observed by the peer so far
  const ObsEpoch* previous_peer_epoch = nullptr;
  for (const auto& pe : peer) {
    bool any = false;
    for (const auto& s : pe.satellites) any = any || take(s.satellite.system);
    if (!any) continue;
    if (!first_peer_epoch) first_peer_epoch = &pe;
    ++c.peer_epochs;
    const std::int64_t key = std::llround(pe.time.toGpsSecondsDouble() * 1000.0);
    peer_times.insert(key);
    const auto it = by_time.find(key);
    if (it == by_time.end()) {
      c.fail("peer epoch " + pe.time.toString() + " missing from ours");
      continue;
    }
    ++c.matched_epochs;
    const ObsEpoch& oe = *it->second;
    struct Advance {
      const ObsEpoch*& previous;
      const ObsEpoch* current;
      ~Advance() { previous = current; }
    } advance{previous_peer_epoch, &pe};
    for (std::size_t i = 0; i < pe.satellites.size(); ++i) {
      const SatelliteId sat = pe.satellites[i].satellite;
      if (!take(sat.system)) continue;
      for (const Observation* p = pe.begin(i); p != pe.end(i); ++p) {
        if (!p->value) continue;
        const std::string where = pe.time.toString(TimeSystem::GPS, 1) + " " + sat.toString() + " " + p->code.toString();
        const Observation* o = oe.find(sat, p->code);
        const bool first_seen = seen.insert({sat.index(), p->code.toString()}).second;
        const bool after_gap = !first_seen && previous_peer_epoch &&
                               !(previous_peer_epoch->find(sat, p->code) && previous_peer_epoch->find(sat, p->code)->value);
        if (!o || !o->value) {
          c.fail(where + ": peer " + std::to_string(*p->value) + ", ours absent");
          continue;
        }
        ++c.compared;
        const double diff = std::fabs(*o->value - *p->value);
        if (diff < 1e-6) {
          ++c.identical;
        } else if (p->code.type == ObservableType::Doppler && diff <= 0.0011) {
          ++c.named["Doppler: RTKLIB float, last digit"];
        } else if (p->code.type == ObservableType::SignalStrength && diff <= 0.0011 &&
                   std::fabs(std::remainder((*o->value + 0.0005) * 16.0, 1.0)) < 1e-6) {
          ++c.named["SNR 1/16 dB-Hz: rounding of x.xxx5"];
        } else {
          c.fail(where + ": peer " + std::to_string(*p->value) + ", ours " + std::to_string(*o->value));
        }
        if (p->code.type == ObservableType::CarrierPhase) {
          const int ours_lli = o->lli.value_or(0), peer_lli = p->lli.value_or(0);
          const int rtklib_expected = (ours_lli & 1) + ((ours_lli & 2) ? 3 : 0);
          if (ours_lli == peer_lli) {
          } else if (first_seen && (peer_lli & 1) && !(ours_lli & 1) &&
                     (peer_lli == 1 || peer_lli == (ours_lli & 2 ? 4 : 1))) {
            ++c.named["LLI 1 at the first observation of a signal"];
          } else if (after_gap && (peer_lli & 1) && !(ours_lli & 1) && (peer_lli & ~1) == (ours_lli & 2 ? 3 : 0)) {
            ++c.named["LLI 1 after an epoch without the signal"];
          } else if ((ours_lli & 2) && rtklib_expected == peer_lli) {
            ++c.named["LLI half-cycle: RTKLIB adds 3"];
          } else {
            c.fail(where + ": LLI peer " + std::to_string(peer_lli) + ", ours " + std::to_string(ours_lli));
          }
        }
      }
    }
  }
  // Observations we have that the peer lacks.
  for (const auto& oe : ours) {
    const std::int64_t key = std::llround((oe.time + peer_shift_s).toGpsSecondsDouble() * 1000.0);
    if (!peer_times.count(key)) continue;
    const ObsEpoch* pe = nullptr;
    for (const auto& e : peer)
      if (std::llround(e.time.toGpsSecondsDouble() * 1000.0) == key) pe = &e;
    for (std::size_t i = 0; i < oe.satellites.size(); ++i) {
      const SatelliteId sat = oe.satellites[i].satellite;
      if (!take(sat.system)) continue;
      const auto& peer_types = peer_header.types(sat.system);
      for (const Observation* o = oe.begin(i); o != oe.end(i); ++o) {
        if (!o->value) continue;
        const Observation* p = pe ? pe->find(sat, o->code) : nullptr;
        if (p && p->value) continue;
        if (std::find(peer_types.begin(), peer_types.end(), o->code) == peer_types.end()) {
          ++c.named["signal without an RTKLIB slot: " + std::string(1, systemLetter(sat.system)) + o->code.toString()];
        } else if (sat.system == GnssSystem::GLONASS && glonass_lost_by_peer && oe.time == *glonass_lost_by_peer) {
          ++c.named["GLONASS MSM skipped by RTKLIB with the damaged frame before it"];
        } else if (sat.system == GnssSystem::GLONASS &&
                   (o->code.type == ObservableType::CarrierPhase || o->code.type == ObservableType::Doppler)) {
          ++c.named["GLONASS phase/Doppler before the first 1020"];
        } else {
          c.fail(oe.time.toString(TimeSystem::GPS, 1) + " " + sat.toString() + " " + o->code.toString() +
                 ": ours " + std::to_string(*o->value) + ", peer blank");
        }
      }
    }
  }
}

void report(const std::string& name, const Comparison& c) {
  std::printf("%s: %zu peer epochs, %zu matched, %zu observations compared, %zu identical\n", name.c_str(),
              c.peer_epochs, c.matched_epochs, c.compared, c.identical);
  for (const auto& [what, n] : c.named) std::printf("  named case: %s: %zu\n", what.c_str(), n);
  for (const auto& f : c.failures) std::printf("  FAIL %s\n", f.c_str());
}

/// Satellite positions and clocks of every peer record against ours (same satellite,
/// toe and kind), at toe and toe +- 1 h (GLONASS: +- 15 min): 1 mm, 0.01 ns.
void compareNavigation(const fs::path& peer_path, const fs::path& ours_path, std::size_t& compared,
                       std::vector<std::string>& failures) {
  const NavData peer = readRinexNav(peer_path.string());
  const NavData ours = readRinexNav(ours_path.string());
  auto check = [&](const std::string& what, const BroadcastState& a, const BroadcastState& b) {
    ++compared;
    const double dpos = (a.position_ecef_m - b.position_ecef_m).norm();
    const double dclk_ns = std::fabs(a.clock_bias_s - b.clock_bias_s) * 1e9;
    if (dpos > 1e-3 || dclk_ns > 0.01)
      failures.push_back(what + ": position " + std::to_string(dpos) + " m, clock " + std::to_string(dclk_ns) + " ns");
  };
  for (const auto& p : peer.gps) {
    const GpsLnavEphemeris* o = nullptr;
    for (const auto& e : ours.gps)
      if (e.satellite == p.satellite && e.orbit.toe == p.orbit.toe && e.iode == p.iode) o = &e;
    if (!o) {
      failures.push_back(p.satellite.toString() + " toe " + p.orbit.toe.toString() + ": no record of ours");
      continue;
    }
    for (double dt : {-3600.0, 0.0, 3600.0})
      check(p.satellite.toString(), satelliteState(p, p.orbit.toe + dt), satelliteState(*o, p.orbit.toe + dt));
  }
  for (const auto& p : peer.galileo) {
    const GalileoEphemeris* o = nullptr;
    for (const auto& e : ours.galileo)
      if (e.satellite == p.satellite && e.orbit.toe == p.orbit.toe && e.iod_nav == p.iod_nav && e.type == p.type) o = &e;
    if (!o) {
      failures.push_back(p.satellite.toString() + " toe " + p.orbit.toe.toString() + ": no record of ours");
      continue;
    }
    for (double dt : {-3600.0, 0.0, 3600.0})
      check(p.satellite.toString(), satelliteState(p, p.orbit.toe + dt), satelliteState(*o, p.orbit.toe + dt));
  }
  for (const auto& p : peer.glonass) {
    const GlonassEphemeris* o = nullptr;
    for (const auto& e : ours.glonass)
      if (e.satellite == p.satellite && e.tb == p.tb) o = &e;
    if (!o) {
      failures.push_back(p.satellite.toString() + " tb " + p.tb.toString() + ": no record of ours");
      continue;
    }
    for (double dt : {-900.0, 0.0, 900.0})
      check(p.satellite.toString(), satelliteState(p, p.tb + dt), satelliteState(*o, p.tb + dt));
  }
}

struct PeerRun {
  fs::path dir, peer_obs, peer_nav, our_obs, our_nav;
  StreamConversion conversion;
};

PeerRun convertBoth(const std::string& input, const std::string& ref_date, const std::string& tag) {
  PeerRun r;
  r.dir = test::tempDir(tag);
  r.peer_obs = r.dir / "peer.obs";
  r.peer_nav = r.dir / "peer.nav";
  r.our_obs = r.dir / "ours.obs";
  r.our_nav = r.dir / "ours.nav";
  EXPECT_TRUE(runConvbin(input, ref_date, r.peer_obs, r.peer_nav)) << "convbin failed on " << input;
  Rtcm3DecoderOptions options;
  options.reference_time = parseReferenceDate(ref_date);
  r.conversion = convertStreamToRinex(input, r.our_obs.string(), r.our_nav.string(), options);
  return r;
}

TEST(Rtcm3Peer, WeekRolloverStr24MatchesConvbin) {
  const std::string input = rtcmPath("week-rollover-STR24.rtcm3");
  REQUIRE_STREAM_AND_CONVBIN(input);
  const PeerRun run = convertBoth(input, "2018/07/14 23:50:00", "str24");
  EXPECT_EQ(run.conversion.counters.count(StreamProblemKind::ChecksumError), 0u);
  Comparison c;
  compareObservations(run.peer_obs, run.our_obs, c, [](GnssSystem) { return true; });
  report("week-rollover-STR24", c);
  EXPECT_EQ(c.peer_epochs, 1134u);  // 23:50:09 .. 00:09:02 at 1 Hz (README: crosses week 2009/2010)
  EXPECT_EQ(c.matched_epochs, c.peer_epochs);
  EXPECT_GT(c.compared, 100000u);
  EXPECT_TRUE(c.failures.empty());
  // The epochs cross the GPS week boundary 2018-07-15 00:00:00 GPST (week 2009 -> 2010).
  RinexObsHeader h;
  const auto ours = readAll(run.our_obs, h);
  ASSERT_FALSE(ours.empty());
  EXPECT_EQ(ours.front().time.gpsWeek().week, 2009);
  EXPECT_EQ(ours.back().time.gpsWeek().week, 2010);
  EXPECT_EQ(h.antenna_type, "LEIAR25.R3");
  EXPECT_EQ(h.receiver_type, "TRIMBLE NETR9");
  ASSERT_TRUE(h.approx_position_ecef_m);
  // README: STR2 IGS position (2020), about 17 cm from the 2018 ARP by plate motion.
  EXPECT_LT((*h.approx_position_ecef_m - Eigen::Vector3d(-4467075.278, 2683011.852, -3667007.010)).norm(), 2.0);

  std::size_t nav_compared = 0;
  std::vector<std::string> nav_failures;
  compareNavigation(run.peer_nav, run.our_nav, nav_compared, nav_failures);
  std::printf("week-rollover-STR24 navigation: %zu satellite states compared\n", nav_compared);
  for (const auto& f : nav_failures) std::printf("  FAIL %s\n", f.c_str());
  EXPECT_GT(nav_compared, 100u);
  EXPECT_TRUE(nav_failures.empty());
}

TEST(Rtcm3Peer, Gmsd7MatchesConvbin) {
  const std::string input = rtcmPath("gmsd7_20121014.rtcm3");
  REQUIRE_STREAM_AND_CONVBIN(input);
  const PeerRun run = convertBoth(input, "2012/10/14 00:00:00", "gmsd7");
  // BeiDou: convbin's epochs are 14 s late (see the header comment).
  Comparison bds;
  compareObservations(run.peer_obs, run.our_obs, bds, [](GnssSystem s) { return s == GnssSystem::BeiDou; }, 14.0);
  report("gmsd7 BeiDou", bds);
  EXPECT_EQ(bds.matched_epochs, bds.peer_epochs);
  EXPECT_GT(bds.compared, 10000u);
  EXPECT_TRUE(bds.failures.empty());
  // The other systems: convbin on the stream without the BeiDou MSM frames.
  const fs::path filtered = run.dir / "no_beidou.rtcm3";
  writeWithoutTypes(input, filtered, 1121, 1127);
  const fs::path peer_obs = run.dir / "peer_no_bds.obs", peer_nav = run.dir / "peer_no_bds.nav";
  ASSERT_TRUE(runConvbin(filtered.string(), "2012/10/14 00:00:00", peer_obs, peer_nav));
  Comparison rest;
  compareObservations(peer_obs, run.our_obs, rest, [](GnssSystem s) { return s != GnssSystem::BeiDou; });
  report("gmsd7 GPS/GLONASS/QZSS", rest);
  EXPECT_EQ(rest.peer_epochs, 257u);  // 23:59:44 .. 00:04:14 (README), 1 Hz with gaps as recorded
  EXPECT_EQ(rest.matched_epochs, rest.peer_epochs);
  EXPECT_GT(rest.compared, 30000u);
  EXPECT_TRUE(rest.failures.empty());

  std::size_t nav_compared = 0;
  std::vector<std::string> nav_failures;
  compareNavigation(run.peer_nav, run.our_nav, nav_compared, nav_failures);
  std::printf("gmsd7 navigation: %zu satellite states compared\n", nav_compared);
  for (const auto& f : nav_failures) std::printf("  FAIL %s\n", f.c_str());
  EXPECT_GT(nav_compared, 30u);
  EXPECT_TRUE(nav_failures.empty());
}

TEST(Rtcm3Peer, Msm7MatchesConvbinAndSkipsProprietaryFrame) {
  const std::string input = rtcmPath("msm7.rtcm");
  REQUIRE_STREAM_AND_CONVBIN(input);
  // The recording has no ephemeris: its week is unknown; any date serves both tools alike.
  const PeerRun run = convertBoth(input, "2026/11/20 00:00:00", "msm7");
  Comparison c;
  // RTKLIB (rtcm3.c input_rtcm3) skips the whole false length of the damaged frame at
  // byte 232 and with it the first epoch's GLONASS MSM at byte 479; we resynchronise.
  compareObservations(run.peer_obs, run.our_obs, c, [](GnssSystem) { return true; }, 0.0,
                      test::gpst(2026, 11, 20, 9, 35, 43));
  report("msm7", c);
  EXPECT_EQ(c.peer_epochs, 36u);
  EXPECT_EQ(c.matched_epochs, c.peer_epochs);
  EXPECT_GT(c.compared, 5000u);
  EXPECT_TRUE(c.failures.empty());
  // README: one proprietary frame (type 3386) to skip. In the file it starts at byte 232
  // with reserved length bits set and is cut by the next frame at byte 479, so it can
  // have no valid CRC (convbin: "rtcm3 parity error: len=646"): the bytes before the
  // first good frame are skipped and counted as garbage; nothing of type 3386 is decoded.
  const auto& by_type = run.conversion.counters.frames_by_type;
  EXPECT_FALSE(by_type.count(3386));
  EXPECT_EQ(run.conversion.counters.garbage_bytes, 479u);
  ASSERT_FALSE(run.conversion.counters.problems.empty());
  EXPECT_EQ(run.conversion.counters.problems.front().kind, StreamProblemKind::Garbage);
  EXPECT_EQ(run.conversion.counters.problems.front().byte_offset, 0u);
  EXPECT_EQ(run.conversion.counters.frames, 182u);
  for (int type : {1077, 1087, 1097, 1107, 1127, 1006, 1008}) EXPECT_TRUE(by_type.count(type)) << type;
}

}  // namespace
}  // namespace ppp
