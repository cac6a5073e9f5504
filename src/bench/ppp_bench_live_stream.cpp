// ppp_bench_live_stream: the input of a TRUE 10 Hz live run for
// scripts/bench_live_realtime.sh --simulate ("no dropped epochs at 10 Hz
// real-time speed"). A simulated flight (simulation/gnss_simulator.h: nominal GPS
// constellation, every error term of the default error model) at --rate Hz is
// written as a receiver's RTCM 3 stream: per epoch one MSM7 GPS message
// (io/rtcm/rtcm3_msm_encoder.h; L1 C/A + L2 of the simulator, lock times from the arcs),
// and a 1005 station frame (the flight's start position: the run's approximate
// position, as ppp_solve would take it) every 10 s; plus a RINEX 3 navigation file
// holding the constellation as GPS LNAV records, for ros.live.navigation_files.
//
// The records: the simulator's satellites move on circular two-body orbits
// (simulation/gps_constellation.h, GM and Earth rotation of IS-GPS-200), which the
// LNAV model (IS-GPS-200 table 20-IV) reproduces exactly with e = 0, no harmonic
// terms and no node rate: at toe = an orbit sample near the flight's middle, the
// orbit plane (inclination, node longitude) comes from two consecutive truth
// samples, the radius and the argument of latitude (taken as M0, omega = 0) from
// the first; Omega0 = node longitude at toe + omega_e toe (the LNAV convention);
// the clock (bias + drift) is the line through the truth clock at toe and at
// toe + 1 h. The program prints the largest difference between the records
// evaluated by BroadcastEphemerisStore and the truth products over the flight
// (orbit 3D, clock), the stream's epochs, frames, bytes and byte rate.
//
// Usage: ppp_bench_live_stream --out-rtcm FILE --out-nav FILE [--minutes M]
//          [--rate HZ] [--profile loiter|survey|figure8|climb] [--seed N] [--satellites N]
// Defaults: 10 min at 10 Hz, loiter, seed 14, 30 satellites.
// Prints figures, asserts nothing.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ppp_bayes_tree/app/caster_stream_builder.h"
#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_writer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_msm_encoder.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/constants.h"

using namespace ppp;

namespace {

/// GPST time at a whole multiple of `step_s` at or before t.
GnssTime floorTo(const GnssTime& t, double step_s) {
  const GpsWeekTime w = t.gpsWeek();
  return GnssTime::fromGpsWeek(w.week, std::floor(w.seconds_of_week / step_s) * step_s);
}

/// A 1005 station frame (RTCM 10403.3 3.5.3: DF025-DF027 in 0.1 mm).
std::vector<std::uint8_t> station1005(const Eigen::Vector3d& arp_ecef_m) {
  BitWriter w;
  w.putUnsigned(1005, 12);
  w.putUnsigned(1, 12);      // DF003 station id
  w.putUnsigned(0, 6);       // DF021 ITRF realisation year
  w.putUnsigned(0b1000, 4);  // DF022-DF024 GPS / GLONASS / Galileo, DF141 reference-station indicator
  w.putSigned(std::llround(arp_ecef_m.x() * 1e4), 38);
  w.putUnsigned(0, 2);  // DF142 single receiver oscillator, DF001 reserved
  w.putSigned(std::llround(arp_ecef_m.y() * 1e4), 38);
  w.putUnsigned(0, 2);  // DF364 quarter cycle indicator
  w.putSigned(std::llround(arp_ecef_m.z() * 1e4), 38);
  return encodeRtcm3Frame(w.bytes());
}

/// A simulated epoch as a receiver's stream epoch (the caster builder's conversion:
/// per signal C/L/D/S, the LLI of the phase, the lock time counted from the start of
/// the signal's arc), with a C/N0 where the simulator writes none (MSM7 carries one).
StreamEpoch toStreamEpoch(const ObsEpoch& in, std::map<std::pair<SatelliteId, std::string>, GnssTime>& arc_start) {
  StreamEpoch out = streamEpochFromRinex(in, arc_start, {});
  for (auto& s : out.satellites)
    for (auto& x : s.signals)
      if (!x.cnr_dbhz) x.cnr_dbhz = 45.0;
  return out;
}

/// The LNAV record reproducing a circular two-body orbit and a linear clock of `truth`.
std::optional<GpsLnavEphemeris> lnavRecord(const EphemerisSource& truth, const SatelliteId& sat, const GnssTime& toe,
                                           double sample_step_s) {
  const auto o1 = truth.satelliteOrbit(sat, toe), o2 = truth.satelliteOrbit(sat, toe + sample_step_s);
  const auto c1 = truth.satelliteClock(sat, toe), c2 = truth.satelliteClock(sat, toe + 3600.0);
  if (!o1.ok() || !o2.ok() || !c1.ok() || !c2.ok()) return std::nullopt;
  const Eigen::Vector3d r1 = o1.value->position_ecef_m;
  // The second sample in the Earth-fixed axes of toe (undo the Earth's rotation since).
  const double theta = kEarthRotationRate_radps * sample_step_s;
  Eigen::Matrix3d R;  // ECEF(t + dt) -> ECEF(t) axes
  R << std::cos(theta), -std::sin(theta), 0, std::sin(theta), std::cos(theta), 0, 0, 0, 1;
  const Eigen::Vector3d r2 = R * o2.value->position_ecef_m;
  const Eigen::Vector3d h = r1.cross(r2).normalized();
  const double i = std::acos(h.z());
  const double node = std::atan2(h.x(), -h.y());  // node longitude at toe (Earth-fixed)
  const double u = std::atan2(r1.z() / std::sin(i), r1.x() * std::cos(node) + r1.y() * std::sin(node));
  const GpsWeekTime w = toe.gpsWeek();
  GpsLnavEphemeris e;
  e.satellite = sat;
  e.week = w.week;
  e.iode = e.iodc = static_cast<int>(std::fmod(w.seconds_of_week / 60.0, 256.0));
  e.ura_m = 2.0;
  e.orbit.toe = toe;
  e.orbit.toe_sow = w.seconds_of_week;
  e.orbit.sqrt_a_sqrtm = std::sqrt(r1.norm());
  e.orbit.i0_rad = i;
  e.orbit.omega0_rad = std::remainder(node + kEarthRotationRate_radps * w.seconds_of_week, 2.0 * kPi);
  e.orbit.m0_rad = u;
  e.clock.toc = toe;
  e.clock.af0_s = c1.value->clock_bias_s;
  e.clock.af1_sps = (c2.value->clock_bias_s - c1.value->clock_bias_s) / 3600.0;
  e.transmission_sow = w.seconds_of_week;
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_rtcm, out_nav, profile = "loiter";
  double minutes = 10.0, rate_hz = 10.0;
  std::uint64_t seed = 14;
  int satellites = 30;
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string a = argv[k], v = argv[k + 1];
    if (a == "--out-rtcm") out_rtcm = v;
    else if (a == "--out-nav") out_nav = v;
    else if (a == "--minutes") minutes = std::atof(v.c_str());
    else if (a == "--rate") rate_hz = std::atof(v.c_str());
    else if (a == "--profile") profile = v;
    else if (a == "--seed") seed = std::strtoull(v.c_str(), nullptr, 10);
    else if (a == "--satellites") satellites = std::atoi(v.c_str());
    else {
      std::fprintf(stderr, "ppp_bench_live_stream: unknown argument %s (see the source's header)\n", a.c_str());
      return 2;
    }
  }
  if (out_rtcm.empty() || out_nav.empty() || !(minutes > 0.0) || !(rate_hz > 0.0)) {
    std::fprintf(stderr, "usage: ppp_bench_live_stream --out-rtcm FILE --out-nav FILE [--minutes M] [--rate HZ] "
                         "[--profile P] [--seed N] [--satellites N]\n");
    return 2;
  }
  SimulationConfig config;
  config.profile = parseFlightProfile(profile);
  config.rate_hz = rate_hz;
  config.duration_s = minutes * 60.0;
  config.satellites = satellites;
  const SimulatedFlight f = simulateFlight(config, seed);
  if (f.epochs.empty()) {
    std::fprintf(stderr, "ppp_bench_live_stream: the simulation gave no epoch\n");
    return 1;
  }
  const GnssTime t0 = f.epochs.front().time, t1 = f.epochs.back().time;

  // Navigation: one LNAV record per satellite at the orbit sample nearest the middle.
  const GnssTime toe = floorTo(t0 + 0.5 * (t1 - t0), config.orbit_interval_s);
  std::ofstream nav(out_nav);
  RinexNavWriter writer(nav);
  writer.writeHeader("ppp_bench_live_stream");
  BroadcastEphemerisStore store;
  int records = 0;
  for (int prn = 1; prn <= satellites; ++prn) {
    const SatelliteId sat{GnssSystem::GPS, prn};
    const auto e = lnavRecord(f.truth_products, sat, toe, config.orbit_interval_s);
    if (!e) continue;
    if (const auto why = store.add(*e)) {
      std::fprintf(stderr, "ppp_bench_live_stream: %s refused: %s\n", sat.toString().c_str(), why->c_str());
      return 1;
    }
    writer.write(*e);
    ++records;
  }
  nav.close();
  double orbit_max_m = 0.0, clock_max_m = 0.0;
  for (GnssTime t = t0; !(t1 < t); t = t + 60.0)
    for (int prn = 1; prn <= satellites; ++prn) {
      const SatelliteId sat{GnssSystem::GPS, prn};
      const auto bo = store.satelliteOrbit(sat, t), to = f.truth_products.satelliteOrbit(sat, t);
      const auto bc = store.satelliteClock(sat, t), tc = f.truth_products.satelliteClock(sat, t);
      if (!bo.ok() || !to.ok() || !bc.ok() || !tc.ok()) continue;
      orbit_max_m = std::max(orbit_max_m, (bo.value->position_ecef_m - to.value->position_ecef_m).norm());
      clock_max_m = std::max(clock_max_m, kSpeedOfLight_mps * std::abs(bc.value->clock_bias_s - tc.value->clock_bias_s));
    }

  // Observations: MSM7 per epoch, a 1005 every 10 s (and first).
  std::ofstream rtcm(out_rtcm, std::ios::binary);
  std::map<std::pair<SatelliteId, std::string>, GnssTime> arc_start;
  MsmEncodeOptions options;
  std::size_t frames = 0, bytes = 0, satellite_epochs = 0;
  std::optional<GnssTime> last_station;
  const Eigen::Vector3d start_ecef_m = f.truth.front().trajectory.position_ecef_m;
  auto put = [&](const std::vector<std::uint8_t>& frame) {
    rtcm.write(reinterpret_cast<const char*>(frame.data()), static_cast<std::streamsize>(frame.size()));
    ++frames;
    bytes += frame.size();
  };
  for (const ObsEpoch& epoch : f.epochs) {
    if (!last_station || epoch.time - *last_station >= 10.0 - 1e-6) {
      put(station1005(start_ecef_m));
      last_station = epoch.time;
    }
    const StreamEpoch e = toStreamEpoch(epoch, arc_start);
    satellite_epochs += e.satellites.size();
    for (const auto& payload : encodeMsm7(e, GnssSystem::GPS, options)) put(encodeRtcm3Frame(payload));
  }
  rtcm.close();
  const double span_s = t1 - t0;
  std::printf("simulated %s flight, seed %llu: %zu epochs at %.1f Hz (%.1f min), %.1f satellites per epoch\n",
              profile.c_str(), static_cast<unsigned long long>(seed), f.epochs.size(), rate_hz, span_s / 60.0,
              static_cast<double>(satellite_epochs) / static_cast<double>(f.epochs.size()));
  std::printf("RTCM 3 stream %s: %zu frames (MSM7 GPS + 1005), %zu bytes, %.0f bytes/s\n", out_rtcm.c_str(), frames,
              bytes, span_s > 0.0 ? static_cast<double>(bytes) / span_s : 0.0);
  std::printf("navigation %s: %d GPS LNAV records, toe %s; against the truth over the flight: orbit 3D max %.4f m, "
              "clock max %.4f m\n",
              out_nav.c_str(), records, toe.toString().c_str(), orbit_max_m, clock_max_m);
  return 0;
}
