// BeiDou broadcast ephemeris (models/broadcast_ephemeris.h): MEO/IGSO and GEO
// user algorithms of BDS-SIS-ICD-B1I 5.2.4.12, on the real records of the ESBC
// day (esbc-2020-177: ESBC00DNK_R_20201770000_01D_MN.rnx, D1 and D2 records,
// GEO C05 among them).
//
// Independent reference: RTKLIB 2.4.3 b34 (Debian package rtklib), run here on
// that navigation file and a synthetic observation file (one B1I pseudorange per
// satellite and epoch; only the transmission time depends on it):
//     rnx2rtkp -p 0 -sys C -x 5 -o out.pos obs.obs ESBC...MN.rnx
// Its trace lines "<transmission time> sat=N rs=X Y Z dts=<ns>" (satposs, trace
// level 4) are compared with our state at the same instant: 4 mm (RTKLIB prints
// mm and the time to 1 us, < 2 mm of motion), clock 0.002 ns (relativistic term
// included on both sides). RTKLIB picks the record with the nearest toe and no
// health filter and up to 6 h from toe, so ours is asked likewise; the epochs sit at 20 and
// 40 minutes past the hour so the nearest toe is never a tie.
//
// The GRG MGEX orbit of that day (GRG0MGXFIN_..._ORB.SP3.gz) carries GPS,
// GLONASS and Galileo only: no precise BeiDou orbit is at hand for the day, so
// the metre-level check is (a) the peer, (b) the GEO's position on the
// geostationary arc (C05 at 58.75 deg E, BDS open service performance standard),
// which a wrong or missing -5 deg rotation misses by kilometres, (c) the
// overlap of consecutive hourly records, and (d) the station's own BeiDou
// pseudoranges (ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz, 00:00-03:00): the
// B1I/B3I (C05: B1I/B2I) ionosphere-free range minus the geometric range from the broadcast
// orbit and clock, the troposphere (modified Hopfield, standard atmosphere) and
// the epoch's common receiver clock, per satellite at the metre level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/models/troposphere.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

namespace ppp {
namespace {

namespace fs = std::filesystem;
using test::gpst;

std::string esbcNav() { return test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_MN.rnx"); }

#define REQUIRE_ESBC_NAV()                                                   \
  if (!fs::exists(esbcNav())) GTEST_SKIP() << "ESBC navigation file absent: " << esbcNav()

const NavData& esbc() {
  static const NavData nav = readRinexNav(esbcNav());
  return nav;
}

double latitudeDeg(const Eigen::Vector3d& p) { return std::atan2(p.z(), std::hypot(p.x(), p.y())) / kDegToRad; }
double longitudeDeg(const Eigen::Vector3d& p) { return std::atan2(p.y(), p.x()) / kDegToRad; }

TEST(BeidouEphemeris, EsbcRecordsAreReadWithGeoAmongThem) {
  REQUIRE_ESBC_NAV();
  const NavData& nav = esbc();
  EXPECT_TRUE(nav.report.clean()) << nav.report.summary();
  std::map<std::string, int> per_sat;
  for (const auto& e : nav.beidou) ++per_sat[e.satellite.toString()];
  // The file's own B_STK comment table: C05 26 records, C06 9, ..., C37 11.
  EXPECT_EQ(per_sat["C05"], 26);
  EXPECT_EQ(per_sat["C06"], 9);
  EXPECT_EQ(per_sat["C37"], 11);
  const BeidouEphemeris& c05 = *std::find_if(nav.beidou.begin(), nav.beidou.end(),
                                             [](const BeidouEphemeris& e) { return e.satellite.prn == 5; });
  EXPECT_TRUE(c05.isGeo());
  // "C05 2020 06 24 22 00 00" is BDT: GPST = BDT + 14 s; toe at the same instant.
  EXPECT_EQ(c05.clock.toc, gpst(2020, 6, 24, 22, 0, 14));
  EXPECT_EQ(c05.orbit.toe, c05.clock.toc);
  EXPECT_EQ(c05.bdt_week, 755);  // GPS week 2111 (2020-06-21..27) - 1356
}

TEST(BeidouEphemeris, GeoSitsOnItsGeostationarySlotAndTheRotationMatters) {
  REQUIRE_ESBC_NAV();
  BroadcastEphemerisStore store;
  store.add(esbc());
  const SatelliteId c05{GnssSystem::BeiDou, 5};
  int checked = 0;
  for (int hour = 0; hour < 24; hour += 3) {
    const GnssTime t = gpst(2020, 6, 25, hour, 20, 0);
    const EphemerisLookup<BeidouEphemeris> r = store.beidou(c05, t);
    ASSERT_TRUE(r) << r.unavailable_reason;
    const Eigen::Vector3d p = satelliteState(*r.record, t).position_ecef_m;
    // Geostationary radius 42164 km, inclination of the BeiDou GEOs below 2 deg,
    // C05 slot 58.75 deg E (station keeping within +-0.5 deg).
    EXPECT_NEAR(p.norm(), 42164e3, 60e3);
    EXPECT_LT(std::fabs(latitudeDeg(p)), 2.0);
    EXPECT_NEAR(longitudeDeg(p), 58.75, 0.5);
    // The MEO/IGSO algorithm applied to the same GEO record is kilometres off.
    const BroadcastState wrong = keplerState(r.record->orbit, beidouKeplerConstants(), t);
    EXPECT_GT((wrong.position_ecef_m - p).norm(), 1e3);
    ++checked;
  }
  EXPECT_EQ(checked, 8);
}

TEST(BeidouEphemeris, ConsecutiveRecordsOverlapAtTheMetreLevel) {
  REQUIRE_ESBC_NAV();
  // Each record evaluated half-way to the next toe of the same satellite (<= 1 h
  // apart): the broadcast fits agree at the metre level, GEO included.
  std::map<SatelliteId, std::vector<const BeidouEphemeris*>> by_sat;
  for (const auto& e : esbc().beidou) by_sat[e.satellite].push_back(&e);
  std::printf("BeiDou record overlap (3D RMS of consecutive records at the mid-point, ESBC 2020-177):\n");
  int satellites = 0;
  for (auto& [sat, list] : by_sat) {
    std::sort(list.begin(), list.end(), [](auto* a, auto* b) { return a->orbit.toe < b->orbit.toe; });
    double sum2 = 0.0, clk2 = 0.0;
    int n = 0;
    for (std::size_t i = 1; i < list.size(); ++i) {
      const double gap = list[i]->orbit.toe - list[i - 1]->orbit.toe;
      if (gap <= 0.0 || gap > 3600.0) continue;
      const GnssTime mid = list[i - 1]->orbit.toe + 0.5 * gap;
      const BroadcastState a = satelliteState(*list[i - 1], mid), b = satelliteState(*list[i], mid);
      sum2 += (a.position_ecef_m - b.position_ecef_m).squaredNorm();
      clk2 += std::pow((a.clock_bias_s - b.clock_bias_s) * 1e9, 2);
      ++n;
    }
    if (n == 0) continue;
    const double rms = std::sqrt(sum2 / n), clk_rms = std::sqrt(clk2 / n);
    std::printf("  %s%s %2d pairs: orbit %.3f m, clock %.3f ns\n", sat.toString().c_str(),
                list.front()->isGeo() ? " (GEO)" : "", n, rms, clk_rms);
    EXPECT_LT(rms, 5.0) << sat.toString();
    ++satellites;
  }
  EXPECT_GE(satellites, 25);
}

// As an EphemerisSource the store serves the BeiDou clock of the B1I/B3I
// ionosphere-free pair, the BeiDou pair of PPP: the record's B3I clock minus
// f1^2 / (f1^2 - f3^2) TGD1 (BDS-SIS-ICD-B1I 3.0, 5.2.4.10: B1I sees the clock
// minus TGD1; f1 = 1561.098 MHz, f3 = 1268.52 MHz). GPS clocks are served as broadcast.
TEST(BeidouEphemeris, StoreClockIsTheB1iB3iIonosphereFreeClock) {
  REQUIRE_ESBC_NAV();
  BroadcastEphemerisStore store;
  store.add(esbc());
  const double f1 = 1561.098, f3 = 1268.52, gamma = f1 * f1 / (f1 * f1 - f3 * f3);
  int compared = 0, nonzero_tgd = 0;
  for (const SatelliteId& sat : esbc().satellites) {
    if (sat.system != GnssSystem::BeiDou && sat.system != GnssSystem::GPS) continue;
    const GnssTime t = gpst(2020, 6, 25, 12, 20);
    const BroadcastLookup st = store.state(sat, t);
    if (!st) continue;
    const auto clock = store.satelliteClock(sat, t);
    ASSERT_TRUE(clock.ok()) << sat.toString();
    double expected_s = st.state->clock_bias_s - st.state->relativistic_s;
    if (sat.system == GnssSystem::BeiDou) {
      const double tgd1_s = store.beidou(sat, t).record->tgd1_s;
      expected_s -= gamma * tgd1_s;
      nonzero_tgd += tgd1_s != 0.0;
    }
    EXPECT_NEAR(clock.value->clock_bias_s, expected_s, 1e-15) << sat.toString();
    ++compared;
  }
  EXPECT_GE(compared, 40);
  EXPECT_GE(nonzero_tgd, 10);  // the file's TGD1 values are ns-level, nonzero
}

TEST(BeidouEphemeris, BeidouRecordsLeaveTheOtherSystemsChoicesAlone) {
  REQUIRE_ESBC_NAV();
  // The same file with and without its BeiDou records: every GPS and Galileo
  // lookup of the day gives the same record and the same state.
  BroadcastEphemerisStore with, without;
  with.add(esbc());
  NavData no_bds = esbc();
  no_bds.beidou.clear();
  without.add(no_bds);
  EXPECT_EQ(with.size(), without.size() + esbc().beidou.size());
  int compared = 0;
  for (const SatelliteId& sat : esbc().satellites) {
    if (sat.system != GnssSystem::GPS && sat.system != GnssSystem::Galileo) continue;
    for (int minute = 0; minute < 24 * 60; minute += 20) {
      const GnssTime t = gpst(2020, 6, 25) + minute * 60.0;
      const BroadcastLookup a = with.state(sat, t), b = without.state(sat, t);
      ASSERT_EQ(static_cast<bool>(a), static_cast<bool>(b)) << sat.toString() << " " << t.toString();
      if (!a) continue;
      EXPECT_EQ(a.state->position_ecef_m, b.state->position_ecef_m);
      EXPECT_EQ(a.state->clock_bias_s, b.state->clock_bias_s);
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
}

TEST(BeidouEphemeris, StationPseudorangesFitTheBroadcastOrbitsAtTheMetreLevel) {
  REQUIRE_ESBC_NAV();
  const std::string obs_path = test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz");
  if (!fs::exists(obs_path)) GTEST_SKIP() << "ESBC observations absent: " << obs_path;
  BroadcastEphemerisStore store;
  store.add(esbc());
  // Header APPROX POSITION (the receiver's own, metre level; enough for a metre-level check).
  const Eigen::Vector3d station(3582105.2910, 532589.7313, 5232754.8054);
  const Geodetic geo = ecefToGeodetic(station);
  const SurfaceMeteo meteo = standardAtmosphere(geo.height_m);
  // B1I with B3I, or with B2I where the receiver has no B3I (C05 at ESBC): BDS-SIS-ICD-B1I
  // 3.0 / B3I 1.0 carrier frequencies.
  const double f1 = 1561.098e6, f2 = 1207.14e6, f3 = 1268.52e6;
  const ObservationCode c2i{ObservableType::Pseudorange, '2', 'I'}, c6i{ObservableType::Pseudorange, '6', 'I'},
      c7i{ObservableType::Pseudorange, '7', 'I'};
  RinexObsReader reader(openObservationSource(obs_path));
  ObsEpoch epoch;
  std::map<SatelliteId, std::pair<double, int>> sum2;  // per satellite: sum of squares, count
  int epochs = 0;
  while (reader.next(epoch) && epoch.time < gpst(2020, 6, 25, 3, 0, 0)) {
    std::vector<std::pair<SatelliteId, double>> raw;  // IF range minus modelled range, receiver clock not removed
    for (const auto& so : epoch.satellites) {
      const SatelliteId sat = so.satellite;
      if (sat.system != GnssSystem::BeiDou) continue;
      const Observation* p1 = epoch.find(sat, c2i);
      const Observation* p3 = epoch.find(sat, c6i);
      const bool b3 = p3 && p3->value;
      if (!b3) p3 = epoch.find(sat, c7i);
      if (!p1 || !p3 || !p1->value || !p3->value) continue;
      const double fb = b3 ? f3 : f2;
      const double k1 = f1 * f1 / (f1 * f1 - fb * fb), kb = fb * fb / (f1 * f1 - fb * fb);
      const double p_if = k1 * *p1->value - kb * *p3->value;
      const auto rec = store.beidou(sat, epoch.time);
      if (!rec) continue;
      // Transmission time by iteration on the range; Earth rotation during the flight.
      GnssTime t_tx = epoch.time - p_if / kSpeedOfLight_mps;
      BroadcastState st;
      double range = 0.0;
      for (int it = 0; it < 3; ++it) {
        st = satelliteState(*rec.record, t_tx);
        const double tau = (st.position_ecef_m - station).norm() / kSpeedOfLight_mps;
        const double a = 7.2921150e-5 * tau;  // CGCS2000 rotation rate
        const Eigen::Vector3d rotated(std::cos(a) * st.position_ecef_m.x() + std::sin(a) * st.position_ecef_m.y(),
                                      -std::sin(a) * st.position_ecef_m.x() + std::cos(a) * st.position_ecef_m.y(),
                                      st.position_ecef_m.z());
        range = (rotated - station).norm();
        t_tx = epoch.time - range / kSpeedOfLight_mps - st.clock_bias_s;
      }
      const double elevation = azimuthElevation(station, st.position_ecef_m).elevation_rad;
      if (elevation < 10.0 * kDegToRad) continue;
      const TroposphereDelays trop = modifiedHopfieldSlantDelays(meteo, elevation, geo.height_m);
      // The broadcast clock refers to B3I; B1I sees it minus TGD1, B2I minus TGD2
      // (BDS-SIS-ICD-B1I 5.2.4.10).
      const double clock_if = st.clock_bias_s - k1 * rec.record->tgd1_s + (b3 ? 0.0 : kb * rec.record->tgd2_s);
      raw.push_back({sat, p_if - range + kSpeedOfLight_mps * clock_if - trop.hydrostatic_m - trop.wet_m});
    }
    if (raw.size() < 5) continue;
    std::vector<double> values;
    for (const auto& [sat, v] : raw) values.push_back(v);
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    const double clock = values[values.size() / 2];  // the epoch's receiver clock (median)
    for (const auto& [sat, v] : raw) {
      sum2[sat].first += (v - clock) * (v - clock);
      sum2[sat].second += 1;
    }
    ++epochs;
  }
  std::printf("ESBC BeiDou ionosphere-free pseudorange minus broadcast range, %d epochs (00:00-03:00, el > 10 deg):\n", epochs);
  int satellites = 0, geo_satellites = 0;
  for (const auto& [sat, s] : sum2) {
    if (s.second < 20) continue;
    const double rms = std::sqrt(s.first / s.second);
    const bool is_geo = isBeidouGeo(sat.prn);
    std::printf("  %s%s %3d epochs: RMS %.2f m\n", sat.toString().c_str(), is_geo ? " (GEO)" : "", s.second, rms);
    EXPECT_LT(rms, 10.0) << sat.toString();
    ++satellites;
    geo_satellites += is_geo;
  }
  EXPECT_GE(epochs, 300);
  EXPECT_GE(satellites, 8);
  EXPECT_GE(geo_satellites, 1);
}

bool haveRnx2rtkp() { return std::system("command -v rnx2rtkp > /dev/null 2>&1") == 0; }

TEST(BeidouEphemeris, MatchesRtklibOnTheEsbcRecords) {
  REQUIRE_ESBC_NAV();
  if (!haveRnx2rtkp()) GTEST_SKIP() << "RTKLIB rnx2rtkp not installed (Debian package rtklib)";
  const std::vector<std::string> sats = {"C05", "C06", "C07", "C11", "C14", "C19", "C23", "C30", "C37"};
  const int hours[] = {0, 4, 9, 13, 17, 22};
  const fs::path dir = test::tempDir("bds_rtklib");
  {
    auto label = [](std::string text, const char* l) {
      text.resize(60, ' ');
      return text + l + "\n";
    };
    std::ofstream obs(dir / "obs.obs");
    obs << label("     3.02           OBSERVATION DATA    M", "RINEX VERSION / TYPE")
        << label("SYNTH", "MARKER NAME") << label("  3512889.0000   781202.0000  5245263.0000", "APPROX POSITION XYZ")
        << label("C    1 C1I", "SYS / # / OBS TYPES")
        << label("  2020     6    25     0    20    0.0000000     GPS", "TIME OF FIRST OBS") << label("", "END OF HEADER");
    char line[96];
    for (int h : hours) {
      for (int minute : {20, 40}) {
        std::snprintf(line, sizeof line, "> 2020 06 25 %02d %02d  0.0000000  0 %2zu\n", h, minute, sats.size());
        obs << line;
        for (const auto& s : sats) obs << s << (s == "C05" ? "  38000000.000\n" : "  22000000.000\n");
      }
    }
  }
  const std::string cmd = "cd '" + dir.string() + "' && rnx2rtkp -p 0 -sys C -x 5 -o out.pos obs.obs '" + esbcNav() +
                          "' > rnx2rtkp.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream trace(dir / "out.pos.trace");
  ASSERT_TRUE(trace) << "no trace file from rnx2rtkp";
  EphemerisSelectionOptions options;
  options.allow_unhealthy = true;
  options.beidou_max_age_s = 6.0 * 3600.0;  // RTKLIB's MAXDTOE_CMP (21600 s)
  BroadcastEphemerisStore store(options);
  store.add(esbc());
  // RTKLIB's satellite number of the first satellite of the first epoch gives its BeiDou numbering.
  std::optional<int> sat_base;
  std::map<std::string, int> compared;
  int geo = 0;
  double worst_m = 0.0, worst_ns = 0.0;
  for (std::string line; std::getline(trace, line);) {
    if (!sat_base && line.find("decode_obsdata: time=") != std::string::npos) {
      sat_base = std::atoi(line.substr(line.find("sat=") + 4).c_str()) - 5;  // sats[0] is C05
      continue;
    }
    const auto rs = line.find(" rs=");
    if (rs == std::string::npos || !sat_base) continue;
    int y, mo, d, h, mi;
    double sec;
    if (std::sscanf(line.c_str(), "4 %d/%d/%d %d:%d:%lf", &y, &mo, &d, &h, &mi, &sec) != 6) continue;
    const int prn = std::atoi(line.substr(line.find("sat=") + 4).c_str()) - *sat_base;
    double x, yy, z, dts_ns;
    if (std::sscanf(line.c_str() + rs, " rs=%lf %lf %lf dts=%lf", &x, &yy, &z, &dts_ns) != 4) continue;
    if (x == 0.0 && yy == 0.0 && z == 0.0) continue;  // RTKLIB found no record within its age limit
    const SatelliteId sat{GnssSystem::BeiDou, prn};
    const GnssTime t = gpst(y, mo, d, h, mi, sec);
    const BroadcastLookup s = store.state(sat, t);
    ASSERT_TRUE(s) << s.unavailable_reason;
    const double dp = (s.state->position_ecef_m - Eigen::Vector3d(x, yy, z)).norm();
    const double dc = std::fabs(s.state->clock_bias_s * 1e9 - dts_ns);
    EXPECT_LT(dp, 4e-3) << sat.toString() << " at " << t.toString();
    EXPECT_LT(dc, 2e-3) << sat.toString() << " at " << t.toString();
    worst_m = std::fmax(worst_m, dp);
    worst_ns = std::fmax(worst_ns, dc);
    ++compared[sat.toString()];
    geo += prn <= 5;
  }
  std::size_t total = 0;
  for (const auto& [sat, n] : compared) total += static_cast<std::size_t>(n);
  std::printf("BeiDou vs RTKLIB rnx2rtkp: %zu states of %zu satellites (%d GEO), max %.4f m, %.4f ns\n", total,
              compared.size(), geo, worst_m, worst_ns);
  EXPECT_GE(compared.size(), 8u);
  EXPECT_GE(geo, 10);
  EXPECT_GE(total, 80u);
}

}  // namespace
}  // namespace ppp
