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
//  - BeiDou navigation records (1042), compared field by field as printed:
//    the transmission time (RINEX A14 field 27). RTCM 1042 carries none: convbin
//    writes its stream time at decoding, we write toe (as for GPS and Galileo).
//    The URA is written in metres by both, the same value: the nominal URA of
//    the index (IS-GPS-200 20.3.3.3.1.1, types/broadcast_accuracy.h).
//  - QZSS navigation records (1044), field by field: the transmission time as
//    for BeiDou; the URA as for BeiDou; the L2 P data flag (1044 has none) 1 in
//    both (IS-QZSS-PNT fixes it to 1).
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
#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_msm_encoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "rinex_nav_fields.h"
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
  for (const auto& p : peer.beidou) {
    const BeidouEphemeris* o = nullptr;
    for (const auto& e : ours.beidou)
      if (e.satellite == p.satellite && e.orbit.toe == p.orbit.toe && e.aode == p.aode) o = &e;
    if (!o) {
      failures.push_back(p.satellite.toString() + " toe " + p.orbit.toe.toString() + ": no record of ours");
      continue;
    }
    for (double dt : {-3600.0, 0.0, 3600.0})
      check(p.satellite.toString(), satelliteState(p, p.orbit.toe + dt), satelliteState(*o, p.orbit.toe + dt));
  }
}

/// BeiDou ('C', RINEX 3.04 table A14) or QZSS ('J', A12) records field by field as
/// printed, with the by-design differences of the header comment named. Returns
/// the fields compared.
std::size_t compareNavFields(const fs::path& peer_path, const fs::path& ours_path, char system,
                             std::map<std::string, std::size_t>& named, std::vector<std::string>& failures) {
  const auto peer = test::readRawNavRecords(peer_path.string(), std::string(1, system));
  const auto ours = test::readRawNavRecords(ours_path.string(), std::string(1, system));
  const std::string name = system == 'C' ? "BeiDou" : "QZSS";
  std::size_t compared = 0;
  for (const auto& p : peer) {
    const test::RawNavRecord* o = nullptr;
    for (const auto& e : ours)
      if (e.satellite == p.satellite && e.epoch == p.epoch && e.fields.size() > 3 && p.fields.size() > 3 &&
          e.fields[3] == p.fields[3])
        o = &e;
    if (!o) {
      failures.push_back(p.satellite + " " + p.epoch + ": no record of ours");
      continue;
    }
    for (std::size_t k = 0; k < 29 && k < p.fields.size(); ++k) {
      const std::string where = p.satellite + " " + p.epoch + " field " + std::to_string(k);
      const std::optional<double> a = p.fields[k];
      const std::optional<double> b = k < o->fields.size() ? o->fields[k] : std::nullopt;
      ++compared;
      if (!a && !b) continue;
      if (!a || !b) {
        failures.push_back(where + ": printed by one writer only");
        continue;
      }
      if (test::agreesToPrintedPrecision(*a, p.text[k], *b, o->text[k])) continue;
      if (k == 27) {
        ++named[name + " transmission time: convbin's stream time, ours toe (the message has none)"];
      } else {
        failures.push_back(where + ": peer " + p.text[k] + ", ours " + o->text[k]);
      }
    }
  }
  return compared;
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

  // BeiDou 1042 records field by field (README: the recording carries 1042).
  std::map<std::string, std::size_t> named;
  std::vector<std::string> field_failures;
  const std::size_t fields = compareNavFields(run.peer_nav, run.our_nav, 'C', named, field_failures);
  const NavData peer_nav = readRinexNav(run.peer_nav.string());
  const NavData our_nav = readRinexNav(run.our_nav.string());
  std::printf("week-rollover-STR24 BeiDou: %zu records (peer), %zu (ours), %zu fields compared\n",
              peer_nav.beidou.size(), our_nav.beidou.size(), fields);
  for (const auto& [what, n] : named) std::printf("  named case: %s: %zu\n", what.c_str(), n);
  for (const auto& f : field_failures) std::printf("  FAIL %s\n", f.c_str());
  EXPECT_GE(peer_nav.beidou.size(), 10u);
  EXPECT_EQ(our_nav.beidou.size(), peer_nav.beidou.size());
  EXPECT_EQ(fields, 29u * peer_nav.beidou.size());
  EXPECT_TRUE(field_failures.empty());
  // GEO records are among them (C01-C05: the rotated user algorithm).
  std::size_t geo = 0;
  for (const auto& e : our_nav.beidou) geo += e.isGeo();
  EXPECT_GT(geo, 0u);

  // QZSS 1044 records field by field (three 1044 frames in the recording).
  std::map<std::string, std::size_t> qzss_named;
  std::vector<std::string> qzss_failures;
  const std::size_t qzss_fields = compareNavFields(run.peer_nav, run.our_nav, 'J', qzss_named, qzss_failures);
  std::printf("week-rollover-STR24 QZSS: %zu fields compared\n", qzss_fields);
  for (const auto& [what, n] : qzss_named) std::printf("  named case: %s: %zu\n", what.c_str(), n);
  for (const auto& f : qzss_failures) std::printf("  FAIL %s\n", f.c_str());
  EXPECT_GE(qzss_fields, 29u);
  EXPECT_TRUE(qzss_failures.empty());
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

// ---------------------------------------------------------------------------
// Decoder behaviour on real recordings, modified in memory.
namespace ppp {
namespace {

std::vector<std::uint8_t> fileBytes(const std::string& path) {
  const std::string s = test::readFileBytes(path);
  return std::vector<std::uint8_t>(s.begin(), s.end());
}

std::vector<Rtcm3Frame> framesOf(const std::vector<std::uint8_t>& bytes) {
  std::vector<Rtcm3Frame> frames;
  Rtcm3Framer framer;
  framer.feed(bytes.data(), bytes.size(), [&](const Rtcm3Frame& f) { frames.push_back(f); });
  return frames;
}

std::vector<std::uint8_t> concat(const std::vector<std::vector<std::uint8_t>>& payloads) {
  std::vector<std::uint8_t> out;
  for (const auto& p : payloads) {
    const auto f = encodeRtcm3Frame(p);
    out.insert(out.end(), f.begin(), f.end());
  }
  return out;
}

struct Decoded {
  std::vector<StreamEpoch> epochs;
  Rtcm3Output nav;
  StreamCounters counters;
  GlonassChannels channels;
};

Decoded decodeAll(const std::vector<std::uint8_t>& bytes, Rtcm3DecoderOptions options, std::size_t chunk = 1 << 20,
                  Rtcm3Decoder::ForeignFrameHandler foreign = nullptr) {
  Rtcm3Decoder decoder(std::move(options));
  if (foreign) decoder.setForeignFrameHandler(foreign);
  Decoded d;
  auto take = [&]() {
    auto& o = decoder.output();
    d.epochs.insert(d.epochs.end(), o.epochs.begin(), o.epochs.end());
    d.nav.gps.insert(d.nav.gps.end(), o.gps.begin(), o.gps.end());
    d.nav.galileo.insert(d.nav.galileo.end(), o.galileo.begin(), o.galileo.end());
    d.nav.glonass.insert(d.nav.glonass.end(), o.glonass.begin(), o.glonass.end());
    d.nav.beidou.insert(d.nav.beidou.end(), o.beidou.begin(), o.beidou.end());
    o.clear();
  };
  for (std::size_t i = 0; i < bytes.size();) {
    const std::size_t step = std::min(chunk == 0 ? 1 + (i * 7919) % 97 : chunk, bytes.size() - i);  // 0: irregular
    decoder.feed(bytes.data() + i, step);
    take();
    i += step;
  }
  decoder.finish();
  take();
  d.counters = decoder.counters();
  d.channels = decoder.glonassChannels();
  return d;
}

Rtcm3DecoderOptions withDate(const std::string& date) {
  Rtcm3DecoderOptions o;
  o.reference_time = parseReferenceDate(date);
  return o;
}

const StreamSatellite* findSat(const StreamEpoch& e, const SatelliteId& s) {
  for (const auto& sat : e.satellites)
    if (sat.satellite == s) return &sat;
  return nullptr;
}

std::size_t countSystem(const StreamEpoch& e, GnssSystem system) {
  std::size_t n = 0;
  for (const auto& s : e.satellites) n += s.satellite.system == system ? 1 : 0;
  return n;
}

#define REQUIRE_STREAM(path) \
  if (!fs::exists(path)) GTEST_SKIP() << "stream recording absent: " << (path)

TEST(Rtcm3Decoder, AnyChunkingGivesTheSameEpochs) {
  const std::string path = rtcmPath("week-rollover-STR24.rtcm3");
  REQUIRE_STREAM(path);
  const auto bytes = fileBytes(path);
  const Decoded whole = decodeAll(bytes, withDate("2018/07/14"));
  const Decoded pieces = decodeAll(bytes, withDate("2018/07/14"), 0);
  ASSERT_EQ(whole.epochs.size(), 1134u);
  ASSERT_EQ(pieces.epochs.size(), whole.epochs.size());
  for (std::size_t i = 0; i < whole.epochs.size(); i += 97) {
    ASSERT_EQ(whole.epochs[i].time, pieces.epochs[i].time);
    ASSERT_EQ(whole.epochs[i].satellites.size(), pieces.epochs[i].satellites.size());
    EXPECT_EQ(whole.epochs[i].satellites[0].signals[0].pseudorange_m, pieces.epochs[i].satellites[0].signals[0].pseudorange_m);
  }
  EXPECT_EQ(whole.nav.gps.size(), pieces.nav.gps.size());
}

TEST(Rtcm3Decoder, WeekFromGalileoEphemerisWithoutReferenceDate) {
  // STR24 carries 1045/1046 (12-bit GST week): once one arrives, the MSM epochs are
  // placed without a reference date, at the same times as with one. The epochs
  // before it are dropped and counted as unresolved time.
  const std::string path = rtcmPath("week-rollover-STR24.rtcm3");
  REQUIRE_STREAM(path);
  const auto bytes = fileBytes(path);
  const Decoded with_ref = decodeAll(bytes, withDate("2018/07/14"));
  const Decoded without = decodeAll(bytes, {});
  EXPECT_GT(without.counters.count(StreamProblemKind::UnresolvedTime), 0u);
  ASSERT_GT(without.epochs.size(), 1000u);
  EXPECT_LT(without.epochs.size(), with_ref.epochs.size());
  EXPECT_EQ(without.epochs.back().time, with_ref.epochs.back().time);
  EXPECT_EQ(without.epochs.back().time, test::gpst(2018, 7, 15, 0, 9, 2));  // README: ends 00:09 GPST
  // GPS records held while the week was unknown are released with the right week.
  ASSERT_FALSE(without.nav.gps.empty());
  for (const auto& e : without.nav.gps) EXPECT_LT(std::fabs(e.orbit.toe - with_ref.epochs.front().time), 86400.0);
}

TEST(Rtcm3Decoder, UnresolvedWeekIsCountedAndNothingIsGuessed) {
  const std::string path = rtcmPath("msm7.rtcm");
  REQUIRE_STREAM(path);
  const Decoded d = decodeAll(fileBytes(path), {});
  EXPECT_TRUE(d.epochs.empty());
  EXPECT_EQ(d.counters.count(StreamProblemKind::UnresolvedTime), 179u);  // every MSM frame (README: no ephemeris)
  ASSERT_GE(d.counters.problems.size(), 2u);
  EXPECT_EQ(d.counters.problems[1].byte_offset, 479u);
}

TEST(Rtcm3Decoder, CrcErrorDropsOneMessageAndTheEpochGoesOn) {
  const std::string path = rtcmPath("msm7.rtcm");
  REQUIRE_STREAM(path);
  auto bytes = fileBytes(path);
  const auto frames = framesOf(bytes);
  // The tenth Galileo MSM7: corrupt one payload byte.
  std::size_t k = 0, seen = 0;
  for (; k < frames.size(); ++k)
    if (frames[k].message_type == 1097 && ++seen == 10) break;
  ASSERT_LT(k, frames.size());
  bytes[frames[k].byte_offset + 20] ^= 0x5A;
  const Decoded good = decodeAll(fileBytes(path), withDate("2026/11/20"));
  const Decoded bad = decodeAll(bytes, withDate("2026/11/20"));
  EXPECT_EQ(bad.counters.count(StreamProblemKind::ChecksumError), 1u);
  bool found = false;
  for (const auto& p : bad.counters.problems)
    if (p.kind == StreamProblemKind::ChecksumError) found = p.byte_offset == frames[k].byte_offset;
  EXPECT_TRUE(found) << "the CRC error names the frame's byte offset";
  ASSERT_EQ(bad.epochs.size(), good.epochs.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < good.epochs.size(); ++i) {
    if (good.epochs[i].satellites.size() == bad.epochs[i].satellites.size()) continue;
    ++differing;
    EXPECT_EQ(countSystem(bad.epochs[i], GnssSystem::Galileo), 0u);
    EXPECT_EQ(countSystem(bad.epochs[i], GnssSystem::GPS), countSystem(good.epochs[i], GnssSystem::GPS));
    EXPECT_EQ(countSystem(bad.epochs[i], GnssSystem::BeiDou), countSystem(good.epochs[i], GnssSystem::BeiDou));
  }
  EXPECT_EQ(differing, 1u);
}

TEST(Rtcm3Decoder, GarbageTruncationUnknownAndForeignFrames) {
  const std::string path = rtcmPath("msm7.rtcm");
  REQUIRE_STREAM(path);
  const auto original = fileBytes(path);
  const auto frames = framesOf(original);
  std::vector<std::vector<std::uint8_t>> payloads;
  for (const auto& f : frames) payloads.push_back(f.payload);
  // An unknown type (4000) in the middle, garbage after the 50th frame, and the
  // stream cut inside its last frame.
  BitWriter w;
  w.putUnsigned(4000, 12);
  w.putUnsigned(0xABCDEF, 24);
  payloads.insert(payloads.begin() + 30, w.bytes());
  auto bytes = concat(payloads);
  const std::size_t frame50 = framesOf(bytes)[50].byte_offset;
  const std::vector<std::uint8_t> junk = {0x00, 0xD3, 0x00, 0x05, 0x12, 0x34, 0x56, 0x78, 0x9A, 0x00, 0x00, 0x00, 0x42};
  bytes.insert(bytes.begin() + static_cast<long>(frame50), junk.begin(), junk.end());
  bytes.resize(bytes.size() - 10);
  const Decoded d = decodeAll(bytes, withDate("2026/11/20"));
  EXPECT_EQ(d.counters.count(StreamProblemKind::UnknownMessage), 1u);
  EXPECT_EQ(d.counters.count(StreamProblemKind::TruncatedFrame), 1u);
  EXPECT_GE(d.counters.count(StreamProblemKind::Garbage), 1u);
  bool garbage_at = false;
  for (const auto& p : d.counters.problems)
    if (p.kind == StreamProblemKind::Garbage && p.byte_offset == frame50) garbage_at = true;
  EXPECT_TRUE(garbage_at);
  EXPECT_EQ(d.epochs.size(), 36u);  // the cut frame was the last epoch's last message: closed at finish()
  // A foreign handler (e.g. the SSR decoder) that consumes type 4000: no longer unknown.
  int consumed = 0;
  const Decoded f = decodeAll(bytes, withDate("2026/11/20"), 1 << 20, [&](const Rtcm3Frame& fr) {
    if (fr.message_type != 4000) return false;
    ++consumed;
    return true;
  });
  EXPECT_EQ(consumed, 1);
  EXPECT_EQ(f.counters.count(StreamProblemKind::UnknownMessage), 0u);
}

TEST(Rtcm3Decoder, ShortMsmIsMalformedAndTheOtherSystemsGoOn) {
  const std::string path = rtcmPath("msm7.rtcm");
  REQUIRE_STREAM(path);
  const auto frames = framesOf(fileBytes(path));
  std::vector<std::vector<std::uint8_t>> payloads;
  std::size_t cut = 0;
  for (const auto& f : frames) {
    payloads.push_back(f.payload);
    if (f.message_type == 1127 && cut == 0) {  // the first BeiDou MSM7 loses its tail
      payloads.back().resize(payloads.back().size() / 2);
      cut = payloads.size();
    }
  }
  const Decoded d = decodeAll(concat(payloads), withDate("2026/11/20"));
  EXPECT_EQ(d.counters.count(StreamProblemKind::MalformedMessage), 1u);
  ASSERT_EQ(d.epochs.size(), 36u);
  EXPECT_EQ(countSystem(d.epochs.front(), GnssSystem::BeiDou), 0u);
  EXPECT_GT(countSystem(d.epochs.front(), GnssSystem::Galileo), 0u);
  EXPECT_GT(countSystem(d.epochs[1], GnssSystem::BeiDou), 0u);
}

TEST(Rtcm3Decoder, InconsistentGpsIodIsRefused) {
  const std::string path = rtcmPath("week-rollover-STR24.rtcm3");
  REQUIRE_STREAM(path);
  const auto frames = framesOf(fileBytes(path));
  std::vector<std::vector<std::uint8_t>> payloads;
  int spoiled = 0;
  for (const auto& f : frames) {
    payloads.push_back(f.payload);
    if (f.message_type == 1019 && spoiled == 0) {
      // IODC (DF071) starts at payload bit 118: flip its last bit, IODE no longer equals its low 8 bits.
      const std::size_t bit = 118 + 9;
      payloads.back()[bit / 8] ^= static_cast<std::uint8_t>(0x80u >> (bit % 8));
      ++spoiled;
    }
  }
  const Decoded good = decodeAll(fileBytes(path), withDate("2018/07/14"));
  const Decoded bad = decodeAll(concat(payloads), withDate("2018/07/14"));
  EXPECT_EQ(good.counters.count(StreamProblemKind::InconsistentEphemeris), 0u);
  EXPECT_EQ(bad.counters.count(StreamProblemKind::InconsistentEphemeris), 1u);
  EXPECT_EQ(bad.nav.gps.size() + 1, good.nav.gps.size());
  for (const auto& e : bad.nav.gps) EXPECT_EQ(e.iodc & 0xFF, e.iode);
}

TEST(Rtcm3Decoder, Msm7RoundTripThroughTheEncoder) {
  // msm7.rtcm decoded, encoded again with encodeMsm7, decoded again: the same
  // observations to the MSM7 resolution (GPS, GLONASS with its channels, Galileo,
  // SBAS, BeiDou; the BeiDou time through BDT and back).
  const std::string path = rtcmPath("msm7.rtcm");
  REQUIRE_STREAM(path);
  const Decoded first = decodeAll(fileBytes(path), withDate("2026/11/20"));
  ASSERT_EQ(first.epochs.size(), 36u);
  MsmEncodeOptions enc;
  enc.glonass_channels = first.channels;
  std::vector<std::vector<std::uint8_t>> payloads;
  const GnssSystem systems[] = {GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo, GnssSystem::SBAS,
                                GnssSystem::BeiDou};
  for (const auto& e : first.epochs) {
    for (std::size_t k = 0; k < 5; ++k) {
      enc.more_messages_follow = k + 1 < 5;
      for (auto& p : encodeMsm7(e, systems[k], enc)) payloads.push_back(std::move(p));
    }
  }
  Rtcm3DecoderOptions options = withDate("2026/11/20");
  options.glonass_channels = first.channels;
  const Decoded second = decodeAll(concat(payloads), options);
  EXPECT_EQ(second.counters.totalProblems(), 0u);
  ASSERT_EQ(second.epochs.size(), first.epochs.size());
  std::size_t compared = 0;
  for (std::size_t i = 0; i < first.epochs.size(); ++i) {
    const auto& a = first.epochs[i];
    const auto& b = second.epochs[i];
    ASSERT_EQ(a.time, b.time);
    ASSERT_EQ(a.satellites.size(), b.satellites.size());
    for (const auto& sa : a.satellites) {
      const StreamSatellite* sb = findSat(b, sa.satellite);
      ASSERT_NE(sb, nullptr) << sa.satellite.toString();
      for (const auto& x : sa.signals) {
        const StreamSignal* y = nullptr;
        for (const auto& s : sb->signals)
          if (s.band == x.band && s.attribute == x.attribute) y = &s;
        ASSERT_NE(y, nullptr);
        auto near = [](const std::optional<double>& u, const std::optional<double>& v, double tol) {
          return u.has_value() == v.has_value() && (!u || std::fabs(*u - *v) <= tol);
        };
        EXPECT_TRUE(near(x.pseudorange_m, y->pseudorange_m, 1e-6))
            << sa.satellite.toString() << " " << x.band << x.attribute << " " << x.pseudorange_m.value_or(0) << " "
            << y->pseudorange_m.value_or(0);
        EXPECT_TRUE(near(x.carrier_phase_cycles, y->carrier_phase_cycles, 1e-6)) << sa.satellite.toString();
        EXPECT_TRUE(near(x.doppler_hz, y->doppler_hz, 1e-6)) << sa.satellite.toString();
        EXPECT_EQ(x.cnr_dbhz, y->cnr_dbhz);
        EXPECT_EQ(x.lli, y->lli);
        EXPECT_EQ(x.lock_time_s, y->lock_time_s);
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 4900u);  // every signal of the 36 epochs
}

TEST(Rtcm3Decoder, LockTimeIndicatorTables) {
  // RTCM 10403.3 DF402: 0 -> 0, i -> 2^(i+4) ms; DF407: piecewise, 704 -> 67108864 ms.
  EXPECT_EQ(msmLockTimeDf402_ms(0), 0u);
  EXPECT_EQ(msmLockTimeDf402_ms(1), 32u);
  EXPECT_EQ(msmLockTimeDf402_ms(15), 524288u);
  EXPECT_EQ(msmLockTimeDf407_ms(63), 63u);
  EXPECT_EQ(msmLockTimeDf407_ms(64), 64u);
  EXPECT_EQ(msmLockTimeDf407_ms(96), 128u);     // 4 i - 256
  EXPECT_EQ(msmLockTimeDf407_ms(160), 512u);    // 16 i - 2048
  EXPECT_EQ(msmLockTimeDf407_ms(703), 67108864u - 1048576u);  // 1048576 i - 671088640
  EXPECT_EQ(msmLockTimeDf407_ms(704), 67108864u);
  for (unsigned i = 0; i <= 704; ++i) EXPECT_EQ(msmLockIndicatorDf407(msmLockTimeDf407_ms(i)), i);
}

}  // namespace
}  // namespace ppp

// The RTCM fuzz entry over its seed corpus (frames made with BitWriter and the MSM7
// encoder) and over cut pieces of the real recordings, so that the entry builds
// with the normal tests and the seeds are known not to throw.
#include "fuzz/rtcm_fuzz_entry.h"

namespace ppp {
namespace {

TEST(RtcmFuzzCorpus, SeedsAndPiecesOfRecordings) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(std::string(PPP_FUZZ_DIR) + "/corpus/rtcm")) {
    const std::string bytes = test::readFileBytes(e.path().string());
    EXPECT_NO_THROW(fuzz::fuzzRtcm(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) << e.path();
    ++n;
  }
  EXPECT_GE(n, 4u);
  for (const std::string name : {"msm7.rtcm", "week-rollover-STR24.rtcm3", "gmsd7_20121014.rtcm3", "clk.rtcm"}) {
    const std::string path = rtcmPath(name);
    if (!fs::exists(path)) continue;
    const std::string bytes = test::readFileBytes(path);
    for (std::size_t start : {std::size_t{0}, bytes.size() / 3, bytes.size() / 2 + 7})
      EXPECT_NO_THROW(fuzz::fuzzRtcm(reinterpret_cast<const std::uint8_t*>(bytes.data()) + start,
                                     std::min<std::size_t>(20000, bytes.size() - start)))
          << name << " from byte " << start;
  }
}

}  // namespace
}  // namespace ppp
