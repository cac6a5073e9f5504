// Timing of the physical models per call (prints figures; not a test).
#include <chrono>
#include <cstdio>

#include "ppp_bayes_tree/models/ocean_loading.h"
#include "ppp_bayes_tree/models/phase_windup.h"
#include "ppp_bayes_tree/models/relativity.h"
#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/models/satellite_eclipse.h"
#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/models/solid_earth_tide.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/models/troposphere.h"

using namespace ppp;

template <class F>
void bench(const char* name, int n, F&& f) {
  volatile double sink = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) sink = sink + f(i);
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / n;
  std::printf("%-36s %9.1f ns/call\n", name, ns);
}

int main() {
  const Eigen::Vector3d rcv(4331299.5841, 567537.7070, 4633133.9645);
  const Eigen::Vector3d sat(15600e3, 7540e3, 20140e3), vel(-1200.0, 2900.0, 100.0);
  const GnssTime t0 = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});
  const SunMoonPositions sm = sunMoonPositionsEcef(t0);
  OceanLoadingCoefficients blq;
  blq.amplitude_radial_m.fill(0.005);
  const int n = 200000;
  bench("sunMoonPositionsEcef", n, [&](int i) { return sunMoonPositionsEcef(t0 + i).sun_ecef_m.x(); });
  bench("solidEarthTide (given Sun/Moon)", n, [&](int i) {
    return solidEarthTideDisplacementEcef_m(rcv + Eigen::Vector3d(i * 1e-3, 0, 0), sm.sun_ecef_m, sm.moon_ecef_m).x();
  });
  bench("oceanLoadingDisplacementEnu", n, [&](int i) { return oceanLoadingDisplacementEnu_m(blq, t0 + i).z(); });
  bench("niellMapping", n, [&](int i) { return niellMapping(0.2 + i * 1e-7, 0.8, 900.0, 133.0).wet; });
  bench("globalMappingFunction", n,
        [&](int i) { return globalMappingFunction(0.2 + i * 1e-7, 0.8, 0.13, 900.0, 61173.0).wet; });
  bench("modifiedHopfieldSlantDelays", n, [&](int i) {
    return modifiedHopfieldSlantDelays(standardAtmosphere(900.0), 0.2 + i * 1e-7, 900.0).hydrostatic_m;
  });
  bench("nominalSatelliteAxes + phaseWindup", n, [&](int i) {
    const Eigen::Vector3d s = sat + Eigen::Vector3d(i, 0, 0);
    const SatelliteBodyAxes a = nominalSatelliteAxes(s, vel, sm.sun_ecef_m);
    return *phaseWindup_cycles(a, northWestAntennaAxes(0.8, 0.13), s, rcv, 0.1);
  });
  bench("shapiro + relativistic clock", n, [&](int i) {
    const Eigen::Vector3d s = sat + Eigen::Vector3d(i, 0, 0);
    return shapiroDelay_m(s, rcv) + relativisticClockCorrection_s(s, vel);
  });
  bench("solveLightTime (analytic orbit)", n, [&](int i) {
    const auto pos = [&](const GnssTime& t) { return rotateForEarthRotation(sat, (t - t0) * 50.0); };
    return solveLightTime(rcv, t0 + i * 1e-3, pos)->flight_time_s;
  });
  bench("sunlightFraction", n, [&](int i) { return sunlightFraction(-sat + Eigen::Vector3d(i, 0, 0), sm.sun_ecef_m); });
  return 0;
}
