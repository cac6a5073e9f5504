#include "ppp_bayes_tree/ppp/model/doppler_observation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {

namespace {

/// d Rz(a) / da, Rz as in rotateForEarthRotation.
Eigen::Vector3d rotationDerivative(const Eigen::Vector3d& v, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {-s * v.x() + c * v.y(), -c * v.x() - s * v.y(), 0.0};
}

/// The light time tau of rho = |Rz(w tau) r_s - r_r| for a satellite state fixed
/// at the transmission time (the state is given there).
double lightTime_s(const Eigen::Vector3d& satellite_ecef_m, const Eigen::Vector3d& receiver_ecef_m) {
  double tau = (satellite_ecef_m - receiver_ecef_m).norm() / kSpeedOfLight_mps;
  for (int i = 0; i < 3; ++i)
    tau = (rotateForEarthRotation(satellite_ecef_m, tau) - receiver_ecef_m).norm() / kSpeedOfLight_mps;
  return tau;
}

}  // namespace

RangeRatePrediction predictRangeRate(const Eigen::Vector3d& satellite_position_ecef_m,
                                     const Eigen::Vector3d& satellite_velocity_ecef_mps,
                                     const Eigen::Vector3d& receiver_ecef_m,
                                     const Eigen::Vector3d& receiver_velocity_ecef_mps) {
  // d/dt of u = Rz(w tau) r_s(t - tau) - r_r(t): Rz v_s (1 - tau') + w tau' Rz' r_s - v_r,
  // tau' = rho' / c, and rho' = e.u'; solved for rho'.
  const double tau = lightTime_s(satellite_position_ecef_m, receiver_ecef_m);
  const double angle = kEarthRotationRate_radps * tau;
  const Eigen::Vector3d u = rotateForEarthRotation(satellite_position_ecef_m, tau) - receiver_ecef_m;
  const Eigen::Vector3d e = u.normalized();
  const Eigen::Vector3d v_s = rotateForEarthRotation(satellite_velocity_ecef_mps, tau);
  const double a = e.dot(v_s - receiver_velocity_ecef_mps);
  const double b =
      e.dot(kEarthRotationRate_radps * rotationDerivative(satellite_position_ecef_m, angle) - v_s) / kSpeedOfLight_mps;
  RangeRatePrediction p;
  p.range_rate_mps = a / (1.0 - b);
  p.d_receiver_velocity = -e / (1.0 - b);
  p.line_of_sight = e;
  p.elevation_rad = azimuthElevation(receiver_ecef_m, receiver_ecef_m + u).elevation_rad;
  return p;
}

double relativisticClockRate_mps(const Eigen::Vector3d& satellite_position_ecef_m,
                                 const Eigen::Vector3d& satellite_velocity_ecef_mps) {
  // d(r.v)/dt = v_i.v_i + r.a_i (r.v is the same in ECEF and inertial axes), a_i = -mu r / |r|^3.
  const Eigen::Vector3d omega(0.0, 0.0, kEarthRotationRate_radps);
  const Eigen::Vector3d v_i = satellite_velocity_ecef_mps + omega.cross(satellite_position_ecef_m);
  const double rv_rate = v_i.squaredNorm() - kGmGps_m3ps2 / satellite_position_ecef_m.norm();
  return -2.0 * rv_rate / kSpeedOfLight_mps;
}

const char* dopplerSkipReasonText(DopplerSkipReason reason) {
  switch (reason) {
    case DopplerSkipReason::NoDoppler: return "no Doppler of the first frequency's signal";
    case DopplerSkipReason::NoClock: return "no satellite clock";
    case DopplerSkipReason::NoOrbit: return "no satellite orbit";
  }
  return "unknown";
}

namespace {

/// The Doppler [Hz] of the signal of `phase` (same band and attribute), when observed.
std::optional<double> dopplerOf(const ObsEpoch& epoch, const SatelliteId& sat, ObservationCode phase) {
  phase.type = ObservableType::Doppler;
  const Observation* o = epoch.find(sat, phase);
  if (!o || !o->value || !std::isfinite(*o->value)) return std::nullopt;
  return *o->value;
}

/// The satellite clock rate without the relativistic term [s/s]: the central
/// difference over +-0.5 s, or a one-sided one over 1 s with the clock `at` t (the
/// caller's answer, not asked again) at the end of the clocks' span.
std::optional<double> clockRate_sps(const EphemerisSource& ephemeris, const SatelliteId& sat, const GnssTime& t,
                                    const EphemerisAnswer<EphemerisClock>& at) {
  constexpr double kHalfStep_s = 0.5;
  const auto rate = [](const auto& a, const auto& b, double dt_s) -> std::optional<double> {
    if (!a.ok() || !b.ok()) return std::nullopt;
    return (b.value->clock_bias_s - a.value->clock_bias_s) / dt_s;
  };
  const auto before = ephemeris.satelliteClock(sat, t - kHalfStep_s);
  const auto after = ephemeris.satelliteClock(sat, t + kHalfStep_s);
  if (auto r = rate(before, after, 2.0 * kHalfStep_s)) return r;
  if (auto r = rate(at, ephemeris.satelliteClock(sat, t + 2.0 * kHalfStep_s), 2.0 * kHalfStep_s)) return r;
  return rate(ephemeris.satelliteClock(sat, t - 2.0 * kHalfStep_s), at, 2.0 * kHalfStep_s);
}

}  // namespace

namespace {

/// A satellite's Doppler signal: the selected pair's first phase signal when the
/// satellite is selected, else the first Doppler (in the header's order) with a
/// pseudorange of the same signal and a known carrier frequency.
struct DopplerSignal {
  ObservationCode code;
  double doppler_hz = 0.0;
  double pseudorange_m = 0.0;
  double frequency_hz = 0.0;
};

std::optional<DopplerSignal> selectedSignal(const ObsEpoch& epoch, const DualFrequencyObservation& s) {
  const std::optional<double> doppler_hz = dopplerOf(epoch, s.satellite, s.phase1);
  if (!doppler_hz || !(s.frequency1_hz > 0.0)) return std::nullopt;
  ObservationCode code = s.phase1;
  code.type = ObservableType::Doppler;
  return DopplerSignal{code, *doppler_hz, s.code1_m, s.frequency1_hz};
}

std::optional<DopplerSignal> firstSignal(const ObsEpoch& epoch, std::size_t i, const GlonassChannels& channels) {
  const SatelliteId sat = epoch.satellites[i].satellite;
  for (const Observation* o = epoch.begin(i); o != epoch.end(i); ++o) {
    if (o->code.type != ObservableType::Doppler || !o->value || !std::isfinite(*o->value)) continue;
    ObservationCode c = o->code;
    c.type = ObservableType::Pseudorange;
    const Observation* code = epoch.find(sat, c);
    const auto f = carrierFrequency_hz(sat.system, c.band,
                                       sat.system == GnssSystem::GLONASS ? channels.channel(sat.prn) : std::nullopt);
    if (!code || !code->value || !(*code->value > 0.0) || !f) continue;
    return DopplerSignal{o->code, *o->value, *code->value, *f};
  }
  return std::nullopt;
}

/// The observation of a signal with the satellite's state at the transmission time.
std::optional<DopplerObservation> withSatelliteState(const SatelliteId& sat, const DopplerSignal& signal,
                                                     const GnssTime& time, const EphemerisSource& ephemeris,
                                                     DopplerSkipReason& why) {
  GnssTime t = time - signal.pseudorange_m / kSpeedOfLight_mps;
  const auto clock = ephemeris.satelliteClock(sat, t);
  const std::optional<double> rate = clock.ok() ? clockRate_sps(ephemeris, sat, t, clock) : std::nullopt;
  why = DopplerSkipReason::NoClock;
  if (!rate) return std::nullopt;
  t -= clock.value->clock_bias_s;
  const auto orbit = ephemeris.satelliteOrbit(sat, t);
  why = DopplerSkipReason::NoOrbit;
  if (!orbit.ok()) return std::nullopt;
  DopplerObservation d;
  d.satellite = sat;
  d.code = signal.code;
  d.wavelength_m = kSpeedOfLight_mps / signal.frequency_hz;
  d.range_rate_mps = -d.wavelength_m * signal.doppler_hz;
  d.satellite_position_ecef_m = orbit.value->position_ecef_m;
  d.satellite_velocity_ecef_mps = orbit.value->velocity_ecef_mps;
  d.satellite_clock_rate_mps = kSpeedOfLight_mps * *rate + relativisticClockRate_mps(d.satellite_position_ecef_m,
                                                                                     d.satellite_velocity_ecef_mps);
  return d;
}

}  // namespace

DopplerEpoch dopplerObservations(const ObsEpoch& epoch, const std::vector<DualFrequencyObservation>& selected,
                                 const std::vector<GnssSystem>& systems, const GlonassChannels& channels,
                                 const EphemerisSource& ephemeris) {
  DopplerEpoch out;
  for (std::size_t i = 0; i < epoch.satellites.size(); ++i) {
    const SatelliteId sat = epoch.satellites[i].satellite;
    if (std::find(systems.begin(), systems.end(), sat.system) == systems.end()) continue;
    const auto s = std::find_if(selected.begin(), selected.end(),
                                [&](const DualFrequencyObservation& o) { return o.satellite == sat; });
    std::optional<DopplerSignal> signal = s != selected.end() ? selectedSignal(epoch, *s) : std::nullopt;
    if (!signal) signal = firstSignal(epoch, i, channels);
    if (!signal) {
      out.skipped.emplace_back(sat, DopplerSkipReason::NoDoppler);
      continue;
    }
    DopplerSkipReason why = DopplerSkipReason::NoDoppler;
    if (auto d = withSatelliteState(sat, *signal, epoch.time, ephemeris, why)) out.observations.push_back(*d);
    else out.skipped.emplace_back(sat, why);
  }
  return out;
}

}  // namespace ppp
