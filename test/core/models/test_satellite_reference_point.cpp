// Satellite reference point (models/satellite_reference_point.h): the offsets
// per convention on a synthetic calibration, the spellings, and at PPP level on
// the real IGS SSRA stream: the satellite position the measurement model uses
// for the GPS III satellites is the SP3 centre of mass + the ionosphere-free PCO
// to the accuracy ppp_ssr_check measures for the stream (L1 convention), and
// 0.7-0.8 m off radially if the stream were taken as ionosphere-free.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "test_support.h"

namespace ppp {
namespace {

using test::dataPath;
using test::gpst;

IonosphereFreeCoefficients gpsL1L2() {
  return ionosphereFreeCoefficients(*carrierFrequency_hz(GnssSystem::GPS, '1'), *carrierFrequency_hz(GnssSystem::GPS, '2'));
}

/// A GPS III-like satellite calibration: L1 and L2 PCO z 1.1858 / 0.6816 m
/// (igs20.atx BLOCK IIIA G080, G01 / G02 NORTH/EAST/UP).
AntennaCalibration gpsIIICalibration(bool with_l2 = true) {
  AntennaCalibration cal;
  cal.type = "BLOCK IIIA";
  cal.satellite = SatelliteId{GnssSystem::GPS, 1};
  FrequencyCalibration l1;
  l1.system = GnssSystem::GPS;
  l1.frequency = 1;
  l1.pco_m = Eigen::Vector3d(-0.06594, 0.02044, 1.18575);
  cal.frequencies.push_back(l1);
  if (with_l2) {
    FrequencyCalibration l2 = l1;
    l2.frequency = 2;
    l2.pco_m = Eigen::Vector3d(-0.06432, 0.02034, 0.68161);
    cal.frequencies.push_back(l2);
  }
  return cal;
}

TEST(SatelliteReferencePoint, OffsetsPerConvention) {
  const AntennaCalibration cal = gpsIIICalibration();
  const auto k = gpsL1L2();
  const Eigen::Vector3d l1 = cal.frequencies[0].pco_m, l2 = cal.frequencies[1].pco_m;
  const Eigen::Vector3d pco_if = k.alpha * l1 + k.beta * l2;
  // IF z = 2.5457 x 1.18575 - 1.5457 x 0.68161 = 1.9650 m: 0.779 m above the L1 centre
  // (the 0.78 m ppp_ssr_check sees radially on SSRA03IGS0 with the wrong convention).
  EXPECT_NEAR(pco_if.z(), 1.9650, 5e-4);

  // From the centre of mass to each point.
  EXPECT_EQ(*satelliteReferenceOffset_m(EphemerisReference::CentreOfMass, nullptr, GnssSystem::GPS, '1', '2', k),
            Eigen::Vector3d::Zero());
  EXPECT_LT((*satelliteReferenceOffset_m(EphemerisReference::AntennaPhaseCentre, &cal, GnssSystem::GPS, '1', '2', k) -
             pco_if).norm(), 1e-12);
  EXPECT_EQ(*satelliteReferenceOffset_m(EphemerisReference::AntennaPhaseCentreL1, &cal, GnssSystem::GPS, '1', '2', k), l1);

  // What the model adds to reach the IF phase centre.
  EXPECT_LT((*ionosphereFreePhaseCentreOffset_m(EphemerisReference::CentreOfMass, &cal, GnssSystem::GPS, '1', '2', k) -
             pco_if).norm(), 1e-12);
  const auto from_l1 = ionosphereFreePhaseCentreOffset_m(EphemerisReference::AntennaPhaseCentreL1, &cal, GnssSystem::GPS, '1', '2', k);
  ASSERT_TRUE(from_l1);
  EXPECT_NEAR(from_l1->z(), 0.7792, 5e-4);
  EXPECT_LT((*from_l1 - (pco_if - l1)).norm(), 1e-12);
  // An IF orbit needs nothing, not even a calibration.
  EXPECT_EQ(*ionosphereFreePhaseCentreOffset_m(EphemerisReference::AntennaPhaseCentre, nullptr, GnssSystem::GPS, '1', '2', k),
            Eigen::Vector3d::Zero());
  // Missing calibration or frequency: nullopt (the model then rejects a
  // centre-of-mass orbit, and takes a zero difference for an L1 orbit, counted).
  EXPECT_FALSE(ionosphereFreePhaseCentreOffset_m(EphemerisReference::CentreOfMass, nullptr, GnssSystem::GPS, '1', '2', k));
  EXPECT_FALSE(ionosphereFreePhaseCentreOffset_m(EphemerisReference::AntennaPhaseCentreL1, nullptr, GnssSystem::GPS, '1', '2', k));
  const AntennaCalibration l1_only = gpsIIICalibration(false);
  EXPECT_TRUE(satelliteReferenceOffset_m(EphemerisReference::AntennaPhaseCentreL1, &l1_only, GnssSystem::GPS, '1', '2', k));
  EXPECT_FALSE(ionosphereFreePhaseCentreOffset_m(EphemerisReference::AntennaPhaseCentreL1, &l1_only, GnssSystem::GPS, '1', '2', k));
}

TEST(SatelliteReferencePoint, SpellingsAndStreamNames) {
  EXPECT_EQ(parseEphemerisReference("com"), EphemerisReference::CentreOfMass);
  EXPECT_EQ(parseEphemerisReference("apc"), EphemerisReference::AntennaPhaseCentre);  // the existing spelling
  EXPECT_EQ(parseEphemerisReference("apc-if"), EphemerisReference::AntennaPhaseCentre);
  EXPECT_EQ(parseEphemerisReference("apc-l1"), EphemerisReference::AntennaPhaseCentreL1);
  EXPECT_FALSE(parseEphemerisReference("APC"));
  EXPECT_FALSE(parseEphemerisReference(""));
  EXPECT_EQ(ssrReferenceFromStreamName("/x/SSRA03IGS0_2026188140760_3epoch.rtcm3"), EphemerisReference::AntennaPhaseCentreL1);
  EXPECT_EQ(ssrReferenceFromStreamName("SSRC00CNE0.rtcm3"), EphemerisReference::CentreOfMass);
  EXPECT_FALSE(ssrReferenceFromStreamName("clk.rtcm"));
  EXPECT_EQ(ephemerisReferenceName(EphemerisReference::AntennaPhaseCentreL1), "antenna phase centre (L1)");
}

struct IgsSsra {
  std::string nav = dataPath("streams/ssr/BRDC00WRD_S_20261880000_01D_MN_GPS_SSR_20261881400.rnx");
  std::string ssr = dataPath("streams/ssr/SSRA03IGS0_2026188140760_3epoch.rtcm3");
  std::string sp3 = dataPath("streams/ssr/IGS0OPSULT_20261870600_02D_15M_ORB_20261881315_07E.SP3");
  std::string atx = dataPath("antex/igs20_gps_satellites_trim.atx");
};

/// Per GPS III satellite and SSR epoch: the model's satellite position minus
/// SP3 + IF PCO, and minus the L1 check (corrected orbit - SP3 - L1 PCO).
struct ModelCheck {
  std::size_t n = 0;
  double rms_m = 0.0, max_radial_m = 0.0;
  double max_against_l1_check_m = 0.0;  // |model diff - ppp_ssr_check's L1 diff|
  std::size_t notes = 0;
};

ModelCheck checkModelPositions(EphemerisReference reference, bool print) {
  const IgsSsra f;
  const NavData nav = readRinexNav(f.nav);
  const SsrStreamFile stream = readSsrStreamFile(f.ssr, gpst(2026, 7, 7, 14, 0, 0));
  // No problems; the GPS C1C id sent twice is counted apart (test_ssr_conventions_real_data).
  EXPECT_EQ(stream.counters.totalProblems(), 0u);
  auto store = std::make_shared<SsrCorrectionStore>();
  for (const auto& m : stream.messages) store->add(m);
  BroadcastSsrOptions options;
  options.reference = reference;
  const BroadcastSsrEphemeris corrected({nav}, store, options);
  PreciseEphemerisOptions sp3_options;
  sp3_options.interpolation_points = 7;  // the cut-out's 7 epochs (13:15-14:45), as ppp_ssr_check
  const PreciseEphemeris sp3 = PreciseEphemeris::load({f.sp3}, {}, sp3_options);
  auto antex = std::make_shared<AntexCalibrations>(std::vector<AntexSource>{{fileBaseName(f.atx), readAntexFile(f.atx)}});
  MeasurementModelOptions model_options;
  model_options.exclude_eclipse = false;
  model_options.receiver_antenna = ReceiverAntennaPolicy::Off;
  const PppMeasurementModel model(corrected, antex, ReceiverAntenna{}, nullptr, model_options);
  const auto k = gpsL1L2();

  ModelCheck out;
  double sum2 = 0.0;
  // The GPS III satellites of the file (igs20: BLOCK IIIA, L1/L2 PCO 0.5 m apart).
  for (const int prn : {1, 4, 11, 14, 18, 21, 23, 28}) {
    const SatelliteId sat{GnssSystem::GPS, prn};
    const auto series = store->orbits().find(sat);
    if (series == store->orbits().end()) continue;
    for (const auto& [t0, entry] : series->second) {
      // A receiver on the ground below the satellite, 67 ms of flight (+ 2 ms, more
      // than any satellite clock offset) after t0: the emission is just after t0.
      const auto at_t0 = sp3.satelliteOrbit(sat, t0);
      if (!at_t0.ok()) continue;
      const Eigen::Vector3d receiver = at_t0.value->position_ecef_m.normalized() * 6378137.0;
      const double range_m = (at_t0.value->position_ecef_m - receiver).norm();
      const GnssTime t_rx = t0 + range_m / kSpeedOfLight_mps + 0.002;
      DualFrequencyObservation o;
      o.satellite = sat;
      o.time = t_rx;
      o.code1 = *ObservationCode::parse("C1C");
      o.code2 = *ObservationCode::parse("C2W");
      o.phase1 = *ObservationCode::parse("L1C");
      o.phase2 = *ObservationCode::parse("L2W");
      o.frequency1_hz = *carrierFrequency_hz(GnssSystem::GPS, '1');
      o.frequency2_hz = *carrierFrequency_hz(GnssSystem::GPS, '2');
      o.code1_m = o.code2_m = range_m;
      o.phase1_cycles = range_m / (kSpeedOfLight_mps / o.frequency1_hz);
      o.phase2_cycles = range_m / (kSpeedOfLight_mps / o.frequency2_hz);
      ReceiverState state;
      state.position_ecef_m = receiver;
      EpochMeasurements measurements;
      std::vector<ModelTerms> terms;
      model.evaluate({o}, {1}, state, nullptr, measurements, &terms);
      EXPECT_EQ(terms.size(), 1u) << sat.toString() << " " << (measurements.rejected.empty() ? "" : measurements.rejected[0].detail);
      if (terms.size() != 1) continue;
      // The emission time as the model finds it (code / c and the corrected clock).
      const GnssTime t_nominal = t_rx - ionosphereFree(range_m, range_m, k) / kSpeedOfLight_mps;
      const GnssTime t_tx = t_nominal - corrected.satelliteClock(sat, t_nominal).value->clock_bias_s;
      const auto com = sp3.satelliteOrbit(sat, t_tx);
      const auto cal = antex->satellite(sat, t_tx);
      EXPECT_TRUE(com.ok() && cal.calibration != nullptr) << sat.toString();
      if (!com.ok() || cal.calibration == nullptr) continue;
      const SatelliteBodyAxes axes =
          nominalSatelliteAxes(com.value->position_ecef_m, com.value->velocity_ecef_mps, sunPositionEcef_m(t_tx));
      const auto body = [&](const Eigen::Vector3d& v) { return Eigen::Vector3d(v.x() * axes.x_ecef + v.y() * axes.y_ecef + v.z() * axes.z_ecef); };
      const Eigen::Vector3d pco_if =
          *satelliteReferenceOffset_m(EphemerisReference::AntennaPhaseCentre, cal.calibration, GnssSystem::GPS, '1', '2', k);
      const Eigen::Vector3d pco_l1 =
          *satelliteReferenceOffset_m(EphemerisReference::AntennaPhaseCentreL1, cal.calibration, GnssSystem::GPS, '1', '2', k);
      const Eigen::Vector3d d = terms[0].satellite_apc_at_transmission_ecef_m - (com.value->position_ecef_m + body(pco_if));
      // ppp_ssr_check's comparison at the same instant: corrected orbit - (SP3 + L1 PCO).
      const Eigen::Vector3d check = corrected.correctedState(sat, t_tx).value->position_ecef_m -
                                    (com.value->position_ecef_m + body(pco_l1));
      const double radial = d.dot(com.value->position_ecef_m.normalized());
      if (print)
        std::printf("%s %s %s: model - (SP3 + IF PCO) %.3f m (radial %+.3f m), ssr_check L1 difference %.3f m\n",
                    std::string(ephemerisReferenceName(reference)).c_str(), sat.toString().c_str(),
                    t0.toString(TimeSystem::GPS, 0).c_str(), d.norm(), radial, check.norm());
      sum2 += d.squaredNorm();
      out.max_radial_m = std::max(out.max_radial_m, std::abs(radial));
      out.max_against_l1_check_m = std::max(out.max_against_l1_check_m, (d - check).norm());
      ++out.n;
    }
  }
  if (out.n > 0) out.rms_m = std::sqrt(sum2 / static_cast<double>(out.n));
  out.notes = model.satelliteReferenceNotes().size();
  return out;
}

TEST(SatelliteReferencePoint, IgsSsraOrbitInTheModelIsSp3PlusIonosphereFreePco) {
  if (!std::filesystem::is_directory(dataPath("streams/ssr"))) GTEST_SKIP() << "no ../shared/data/streams (set PPP_SHARED_DATA)";
  // The stream's name declares the L1 phase centre.
  EXPECT_EQ(ssrReferenceFromStreamName(IgsSsra{}.ssr), EphemerisReference::AntennaPhaseCentreL1);
  const ModelCheck l1 = checkModelPositions(EphemerisReference::AntennaPhaseCentreL1, true);
  // 8 GPS III satellites x the stream's 3 GPS orbit epochs (14:07:40, :50, 14:08:00).
  EXPECT_EQ(l1.n, 24u);
  // ppp_ssr_check on this stream (L1): GPS III 3D RMS 0.034-0.055 m per satellite,
  // 0.070 m for all 30 satellites. The model's position carries exactly that error:
  EXPECT_LT(l1.rms_m, 0.08);
  EXPECT_LT(l1.max_radial_m, 0.06);
  EXPECT_LT(l1.max_against_l1_check_m, 1e-3);  // the IF - L1 difference added exactly
  EXPECT_EQ(l1.notes, 0u);                      // every GPS III satellite has its ANTEX entry
  std::printf("L1 convention: %zu satellite-epochs, 3D RMS %.4f m, max radial %.4f m, vs ssr_check %.2e m\n", l1.n,
              l1.rms_m, l1.max_radial_m, l1.max_against_l1_check_m);

  // The same stream taken as ionosphere-free (what the model did before): the
  // GPS III orbits sit 0.72-0.81 m too low.
  const ModelCheck as_if = checkModelPositions(EphemerisReference::AntennaPhaseCentre, false);
  EXPECT_EQ(as_if.n, 24u);
  EXPECT_GT(as_if.rms_m, 0.6);
  EXPECT_GT(as_if.max_radial_m, 0.7);
  std::printf("taken as IF: 3D RMS %.4f m, max radial %.4f m\n", as_if.rms_m, as_if.max_radial_m);
}

TEST(SatelliteReferencePoint, L1OrbitWithoutSatelliteCalibrationIsUsedAndCounted) {
  if (!std::filesystem::is_directory(dataPath("streams/ssr"))) GTEST_SKIP() << "no ../shared/data/streams (set PPP_SHARED_DATA)";
  const IgsSsra f;
  const NavData nav = readRinexNav(f.nav);
  const SsrStreamFile stream = readSsrStreamFile(f.ssr, gpst(2026, 7, 7, 14, 0, 0));
  auto store = std::make_shared<SsrCorrectionStore>();
  for (const auto& m : stream.messages) store->add(m);
  BroadcastSsrOptions options;
  options.reference = EphemerisReference::AntennaPhaseCentreL1;
  const BroadcastSsrEphemeris corrected({nav}, store, options);
  // An ANTEX file with receivers only: no satellite calibration at all.
  const std::string receivers = dataPath("antex/igs05_esbc_receiver_trim.atx");
  auto antex = std::make_shared<AntexCalibrations>(std::vector<AntexSource>{{fileBaseName(receivers), readAntexFile(receivers)}});
  MeasurementModelOptions model_options;
  model_options.exclude_eclipse = false;
  model_options.receiver_antenna = ReceiverAntennaPolicy::Off;
  const PppMeasurementModel model(corrected, antex, ReceiverAntenna{}, nullptr, model_options);
  const SatelliteId g04{GnssSystem::GPS, 4};
  const GnssTime t0 = store->orbits().at(g04).begin()->first;
  const Eigen::Vector3d sat_pos = corrected.correctedState(g04, t0).value->position_ecef_m;
  const Eigen::Vector3d receiver = sat_pos.normalized() * 6378137.0;
  const double range_m = (sat_pos - receiver).norm();
  DualFrequencyObservation o;
  o.satellite = g04;
  o.time = t0 + range_m / kSpeedOfLight_mps + 0.002;
  o.code1 = *ObservationCode::parse("C1C");
  o.code2 = *ObservationCode::parse("C2W");
  o.phase1 = *ObservationCode::parse("L1C");
  o.phase2 = *ObservationCode::parse("L2W");
  o.frequency1_hz = *carrierFrequency_hz(GnssSystem::GPS, '1');
  o.frequency2_hz = *carrierFrequency_hz(GnssSystem::GPS, '2');
  o.code1_m = o.code2_m = range_m;
  o.phase1_cycles = range_m * o.frequency1_hz / kSpeedOfLight_mps;
  o.phase2_cycles = range_m * o.frequency2_hz / kSpeedOfLight_mps;
  ReceiverState state;
  state.position_ecef_m = receiver;
  EpochMeasurements measurements;
  std::vector<ModelTerms> terms;
  for (int epoch = 0; epoch < 3; ++epoch) model.evaluate({o}, {1}, state, nullptr, measurements, &terms);
  // Used (not rejected), with a zero difference, and counted once per evaluation.
  ASSERT_EQ(terms.size(), 1u) << (measurements.rejected.empty() ? "" : measurements.rejected[0].detail);
  EXPECT_EQ(terms[0].satellite_reference_offset_ecef_m, Eigen::Vector3d::Zero());
  const auto notes = model.satelliteReferenceNotes();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("G04"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("3 satellite-epoch(s)"), std::string::npos) << notes[0];
}

}  // namespace
}  // namespace ppp
