// Doppler range rates (doppler_observation.h): the range-rate model against the
// numerical derivative of the light-time geometric range with the Earth's rotation
// (satellite and receiver moving), the relativistic clock rate against the
// numerical derivative of -2 r.v / c^2 on a Kepler orbit, and the sign of the
// observation formed from a Doppler (positive for an approaching satellite,
// RINEX 3.05 section 5.2.3).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <optional>

#include "ppp_bayes_tree/models/relativity.h"
#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/ppp/model/doppler_observation.h"
#include "ppp_bayes_tree/types/constants.h"

namespace {

using Eigen::Vector3d;
using ppp::GnssTime;

const GnssTime kT0 = GnssTime::fromGpsWeek(2370, 345600.0);
const Vector3d kReceiver(4331299.5841, 567537.7070, 4633133.9645);  // ZIM2 (data README)

/// A satellite moving with constant acceleration in ECEF, a receiver at constant velocity.
struct Motion {
  Vector3d sat0{15.0e6, -8.0e6, 20.0e6};
  Vector3d sat_v{1800.0, 2400.0, -600.0};
  Vector3d sat_a{-0.3, 0.2, -0.5};
  Vector3d rx_v{1.5, -2.0, 0.7};
  Vector3d satellite(const GnssTime& t) const {
    const double s = t - kT0;
    return sat0 + sat_v * s + 0.5 * sat_a * s * s;
  }
  Vector3d satelliteVelocity(const GnssTime& t) const { return sat_v + sat_a * (t - kT0); }
  Vector3d receiver(const GnssTime& t) const { return kReceiver + rx_v * (t - kT0); }
  ppp::LightTimeSolution range(const GnssTime& t) const {
    return *ppp::solveLightTime(receiver(t), t, [this](const GnssTime& tx) { return satellite(tx); }, 1e-15, 20);
  }
};

TEST(DopplerObservation, RangeRateIsTheDerivativeOfTheLightTimeRange) {
  const Motion m;
  const GnssTime t = kT0 + 10.0;
  constexpr double h = 0.05;
  const double numerical = (m.range(t + h).range_m - m.range(t - h).range_m) / (2.0 * h);
  const ppp::LightTimeSolution lt = m.range(t);
  const ppp::RangeRatePrediction p = ppp::predictRangeRate(
      lt.satellite_ecef_at_transmission_m, m.satelliteVelocity(lt.transmission_time), m.receiver(t), m.rx_v);
  EXPECT_NEAR(p.range_rate_mps, numerical, 2e-5);
  // The derivative with respect to the receiver velocity is minus the line of sight.
  EXPECT_LT((p.d_receiver_velocity + (lt.satellite_ecef_m - m.receiver(t)).normalized()).norm(), 1e-4);
  // The Earth's rotation and light-time terms matter at this tolerance: the plain
  // e.(v_s - v_r) of the unrotated positions misses by millimetres per second.
  const Vector3d e = (lt.satellite_ecef_at_transmission_m - m.receiver(t)).normalized();
  EXPECT_GT(std::abs(e.dot(m.satelliteVelocity(lt.transmission_time) - m.rx_v) - numerical), 1e-3);
}

TEST(DopplerObservation, ReceiverMovingTowardsTheSatelliteShortensTheRange) {
  const Motion m;
  const ppp::LightTimeSolution lt = m.range(kT0);
  const Vector3d towards = (lt.satellite_ecef_m - kReceiver).normalized();
  const ppp::RangeRatePrediction still =
      ppp::predictRangeRate(lt.satellite_ecef_at_transmission_m, m.sat_v, kReceiver, Vector3d::Zero());
  const ppp::RangeRatePrediction moving =
      ppp::predictRangeRate(lt.satellite_ecef_at_transmission_m, m.sat_v, kReceiver, 2.0 * towards);
  EXPECT_NEAR(moving.range_rate_mps - still.range_rate_mps, -2.0, 1e-4);
}

/// Two-body motion in inertial axes (RK4), a = -mu r / |r|^3.
void keplerStep(Vector3d& r, Vector3d& v, double dt) {
  const auto acc = [](const Vector3d& p) { return Vector3d(-ppp::kGmGps_m3ps2 * p / std::pow(p.norm(), 3)); };
  const Vector3d k1r = v, k1v = acc(r);
  const Vector3d k2r = v + 0.5 * dt * k1v, k2v = acc(r + 0.5 * dt * k1r);
  const Vector3d k3r = v + 0.5 * dt * k2v, k3v = acc(r + 0.5 * dt * k2r);
  const Vector3d k4r = v + dt * k3v, k4v = acc(r + dt * k3r);
  r += dt / 6.0 * (k1r + 2.0 * k2r + 2.0 * k3r + k4r);
  v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
}

TEST(DopplerObservation, RelativisticClockRateIsTheDerivativeOfTheTerm) {
  // An eccentric orbit (e about 0.1) away from perigee, inertial axes = ECEF at t = 0.
  const Vector3d r0(20.0e6, 10.0e6, 5.0e6), v0(-1500.0, 3200.0, 1200.0);
  const auto term_m = [&](double dt) {
    Vector3d r = r0, v = v0;
    keplerStep(r, v, dt);
    return ppp::kSpeedOfLight_mps * ppp::relativisticClockCorrection_s(r, v);
  };
  const double numerical = (term_m(1.0) - term_m(-1.0)) / 2.0;
  const Vector3d omega(0.0, 0.0, ppp::kEarthRotationRate_radps);
  const Vector3d v_ecef = v0 - omega.cross(r0);
  EXPECT_GT(std::abs(numerical), 1e-3);  // the term's rate is not negligible here
  EXPECT_NEAR(ppp::relativisticClockRate_mps(r0, v_ecef), numerical, 1e-6);
}

/// A satellite with a constant clock drift at a fixed position and velocity.
class FixedEphemeris : public ppp::EphemerisSource {
 public:
  Vector3d position{15.0e6, -8.0e6, 20.0e6};
  Vector3d velocity{0.0, 0.0, 0.0};
  double drift_sps = 1e-9;
  std::optional<GnssTime> clock_end;  // no clock after this time (the end of the clocks' span)
  mutable int clock_queries = 0;
  ppp::EphemerisAnswer<ppp::EphemerisClock> satelliteClock(const ppp::SatelliteId&, const GnssTime& t) const override {
    ++clock_queries;
    if (clock_end && t - *clock_end > 0.0)
      return ppp::EphemerisAnswer<ppp::EphemerisClock>::unavailable(ppp::EphemerisUnavailable::OutsideSpan, "after the clocks");
    return ppp::EphemerisAnswer<ppp::EphemerisClock>::success({1e-4 + drift_sps * (t - kT0), drift_sps, std::nullopt});
  }
  ppp::EphemerisAnswer<ppp::EphemerisOrbit> satelliteOrbit(const ppp::SatelliteId&, const GnssTime&) const override {
    ppp::EphemerisOrbit o;
    o.position_ecef_m = position;
    o.velocity_ecef_mps = velocity;
    return ppp::EphemerisAnswer<ppp::EphemerisOrbit>::success(o);
  }
  std::string describeSource() const override { return "fixed"; }
};

/// G05 observed with L1C and a D1C of +1000 Hz at kT0, and its selected L1 signal.
struct G05Doppler {
  ppp::ObsEpoch epoch;
  ppp::DualFrequencyObservation s;
  G05Doppler() {
    epoch.time = kT0;
    const ppp::SatelliteId g05{ppp::GnssSystem::GPS, 5};
    epoch.satellites.push_back({g05, 0, 2});
    epoch.observations.push_back({*ppp::ObservationCode::parse("L1C"), 1.0e8, std::nullopt, std::nullopt});
    epoch.observations.push_back({*ppp::ObservationCode::parse("D1C"), 1000.0, std::nullopt, std::nullopt});
    s.satellite = g05;
    s.phase1 = *ppp::ObservationCode::parse("L1C");
    s.frequency1_hz = 1575.42e6;
    s.code1_m = 2.2e7;
  }
};

TEST(DopplerObservation, PositiveDopplerIsAnApproachingSatellite) {
  G05Doppler g;
  ppp::ObsEpoch& epoch = g.epoch;
  const ppp::DualFrequencyObservation& s = g.s;
  const FixedEphemeris ephemeris;
  const ppp::DopplerEpoch d = ppp::dopplerObservations(epoch, {s}, {ppp::GnssSystem::GPS}, {}, ephemeris);
  ASSERT_EQ(d.observations.size(), 1u);
  const double lambda = ppp::kSpeedOfLight_mps / 1575.42e6;
  EXPECT_NEAR(d.observations[0].range_rate_mps, -1000.0 * lambda, 1e-9);  // approaching: range shrinks
  EXPECT_EQ(d.observations[0].code.toString(), "D1C");
  // The satellite clock rate: c x drift plus the relativistic rate of its state.
  EXPECT_NEAR(d.observations[0].satellite_clock_rate_mps,
              ppp::kSpeedOfLight_mps * 1e-9 + ppp::relativisticClockRate_mps(ephemeris.position, ephemeris.velocity),
              1e-6);
  // A satellite without the first frequency's Doppler is skipped with the reason.
  epoch.observations[1].value.reset();
  const ppp::DopplerEpoch none = ppp::dopplerObservations(epoch, {s}, {ppp::GnssSystem::GPS}, {}, ephemeris);
  EXPECT_TRUE(none.observations.empty());
  ASSERT_EQ(none.skipped.size(), 1u);
  EXPECT_EQ(none.skipped[0].second, ppp::DopplerSkipReason::NoDoppler);
}

TEST(DopplerObservation, ASatelliteWithoutADualFrequencyPairUsesItsFirstDopplerWithACode) {
  // The Doppler needs no pair: a single-frequency Galileo satellite's D1X, with C1X
  // for the transmission time; a system not processed is left out.
  ppp::ObsEpoch epoch;
  epoch.time = kT0;
  const ppp::SatelliteId e11{ppp::GnssSystem::Galileo, 11};
  const ppp::SatelliteId c20{ppp::GnssSystem::BeiDou, 20};
  epoch.satellites.push_back({e11, 0, 3});
  epoch.satellites.push_back({c20, 3, 2});
  epoch.observations.push_back({*ppp::ObservationCode::parse("D5X"), std::nullopt, std::nullopt, std::nullopt});
  epoch.observations.push_back({*ppp::ObservationCode::parse("C1X"), 2.4e7, std::nullopt, std::nullopt});
  epoch.observations.push_back({*ppp::ObservationCode::parse("D1X"), -500.0, std::nullopt, std::nullopt});
  epoch.observations.push_back({*ppp::ObservationCode::parse("C2I"), 3.8e7, std::nullopt, std::nullopt});
  epoch.observations.push_back({*ppp::ObservationCode::parse("D2I"), 100.0, std::nullopt, std::nullopt});
  const FixedEphemeris ephemeris;
  const ppp::DopplerEpoch d =
      ppp::dopplerObservations(epoch, {}, {ppp::GnssSystem::GPS, ppp::GnssSystem::Galileo}, {}, ephemeris);
  ASSERT_EQ(d.observations.size(), 1u);
  EXPECT_EQ(d.observations[0].satellite, e11);
  EXPECT_EQ(d.observations[0].code.toString(), "D1X");
  EXPECT_NEAR(d.observations[0].range_rate_mps, 500.0 * ppp::kSpeedOfLight_mps / 1575.42e6, 1e-9);  // receding
}

// The clock is asked once at the transmission time, for the bias and the rate:
// the rate adds the two times +-0.5 s around it (the central difference), and at
// the end of the clocks' span the one-sided difference reuses the answer at the
// transmission time.
TEST(DopplerObservation, TheSatelliteClockIsAskedOnceAtTheTransmissionTime) {
  G05Doppler g;
  ppp::ObsEpoch& epoch = g.epoch;
  const ppp::DualFrequencyObservation& s = g.s;
  FixedEphemeris ephemeris;
  const double expected_mps =
      ppp::kSpeedOfLight_mps * 1e-9 + ppp::relativisticClockRate_mps(ephemeris.position, ephemeris.velocity);
  ppp::DopplerEpoch d = ppp::dopplerObservations(epoch, {s}, {ppp::GnssSystem::GPS}, {}, ephemeris);
  ASSERT_EQ(d.observations.size(), 1u);
  EXPECT_NEAR(d.observations[0].satellite_clock_rate_mps, expected_mps, 1e-6);
  EXPECT_EQ(ephemeris.clock_queries, 3);  // t, t - 0.5 s, t + 0.5 s
  // The clocks end 0.2 s after the transmission time (~0.07 s before the epoch):
  // t + 0.5 s and t + 1 s have none, the rate is the one-sided difference t - 1 s to t.
  ephemeris.clock_queries = 0;
  ephemeris.clock_end = kT0 - 2.2e7 / ppp::kSpeedOfLight_mps + 0.2;
  d = ppp::dopplerObservations(epoch, {s}, {ppp::GnssSystem::GPS}, {}, ephemeris);
  ASSERT_EQ(d.observations.size(), 1u);
  EXPECT_NEAR(d.observations[0].satellite_clock_rate_mps, expected_mps, 1e-6);
  EXPECT_EQ(ephemeris.clock_queries, 5);  // t, t -+ 0.5 s, t + 1 s, t - 1 s
}

}  // namespace
