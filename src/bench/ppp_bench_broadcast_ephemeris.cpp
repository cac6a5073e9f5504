// Throughput of the broadcast ephemeris models: one GPS Keplerian evaluation
// (IS-GPS-200 table 20-IV with velocity) and one GLONASS state integrated over
// 15 min (30 s Runge-Kutta steps), plus a store lookup among 13 records per
// satellite. Prints figures; asserts nothing.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"

using namespace ppp;
using Clock = std::chrono::steady_clock;

namespace {

// Elements of the public G01 record of 2025-06-15 02:00 (ESOC BRDC, see
// test/fixtures/rinex_nav/mixed_v304.nav).
GpsLnavEphemeris gpsRecord(int satellite, double toe_offset_s) {
  GpsLnavEphemeris e;
  e.satellite = SatelliteId{GnssSystem::GPS, satellite};
  e.orbit.toe = GnssTime::fromGpsWeek(2371, 7200.0) + toe_offset_s;
  e.orbit.toe_sow = 7200.0 + toe_offset_s;
  e.clock.toc = e.orbit.toe;
  e.clock.af0_s = 2.915360964835e-04;
  e.orbit.sqrt_a_sqrtm = 5.153723411560e+03;
  e.orbit.eccentricity = 5.672341212630e-04;
  e.orbit.i0_rad = 9.592069088751e-01;
  e.orbit.omega0_rad = 1.493825366040e+00 + 0.5 * satellite;
  e.orbit.omega_rad = 2.336450295333e-01;
  e.orbit.m0_rad = 2.172069051852e+00 + 0.3 * satellite;
  e.orbit.delta_n_radps = 4.410898017322e-09;
  e.orbit.omega_dot_radps = -8.210341993700e-09;
  e.orbit.idot_radps = 2.364384200378e-10;
  e.orbit.cuc_rad = 4.749745130539e-06;
  e.orbit.cus_rad = 4.006549715996e-06;
  e.orbit.crs_m = 9.159375000000e+01;
  e.orbit.crc_m = 2.984687500000e+02;
  return e;
}

template <typename F>
double nanosecondsPerCall(int n, F&& f) {
  const auto start = Clock::now();
  for (int i = 0; i < n; ++i) f(i);
  return std::chrono::duration<double, std::nano>(Clock::now() - start).count() / n;
}

}  // namespace

int main() {
  volatile double sink = 0.0;
  const GpsLnavEphemeris g = gpsRecord(1, 0.0);
  const double kepler_ns = nanosecondsPerCall(1000000, [&](int i) {
    sink = sink + satelliteState(g, g.orbit.toe + 0.001 * i).position_ecef_m.x();
  });

  GlonassEphemeris r;
  r.satellite = SatelliteId{GnssSystem::GLONASS, 1};
  r.tb = g.orbit.toe;
  r.position_m = {1.090894238281e+07, -2.885726074219e+06, 2.288353955078e+07};
  r.velocity_mps = {1.407806396484e+03, 2.795855522156e+03, -3.169984817505e+02};
  const double glonass_ns = nanosecondsPerCall(20000, [&](int i) {
    sink = sink + satelliteState(r, r.tb + 900.0 + 1e-3 * i).position_ecef_m.x();
  });

  BroadcastEphemerisStore store;
  for (int prn = 1; prn <= 32; ++prn) {
    for (int k = 0; k < 13; ++k) store.add(gpsRecord(prn, 7200.0 * k - 43200.0));
  }
  const double lookup_ns = nanosecondsPerCall(200000, [&](int i) {
    const SatelliteId sat{GnssSystem::GPS, 1 + i % 32};
    if (auto s = store.state(sat, g.orbit.toe + 30.0 * (i % 1000))) sink = sink + s.state->clock_bias_s;
  });

  std::printf("GPS Keplerian position+velocity+clock: %8.1f ns/call\n", kepler_ns);
  std::printf("GLONASS RK4 over 15 min (30 steps):    %8.1f ns/call\n", glonass_ns);
  std::printf("store lookup + state (416 records):    %8.1f ns/call\n", lookup_ns);
  return 0;
}
