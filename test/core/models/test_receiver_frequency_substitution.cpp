// Receiver antenna frequency substitution (receiver_frequency_substitution.h):
// the per-system table of GPS stand-ins and the lookup on a receiver block that
// holds G01/G02 only (as igs05.atx and igs20_zim2_gps_trim.atx do).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ppp_bayes_tree/models/receiver_frequency_substitution.h"

namespace ppp {
namespace {

FrequencyCalibration gpsFrequency(int number, double north_m, double east_m, double up_m) {
  FrequencyCalibration f;
  f.system = GnssSystem::GPS;
  f.frequency = number;
  f.pco_m = Eigen::Vector3d(north_m, east_m, up_m);
  return f;
}

// A choke ring with GPS values only (ASH701945E_M SCIS of igs05_esbc_receiver_trim.atx
// has this shape: G01 and G02, no other system).
AntennaCalibration gpsOnlyReceiver() {
  AntennaCalibration a;
  a.type = "ASH701945E_M    SCIS";
  a.model = "ASH701945E_M";
  a.radome = "SCIS";
  a.frequencies = {gpsFrequency(1, 0.0011, -0.0002, 0.0914), gpsFrequency(2, -0.0003, 0.0004, 0.1198)};
  return a;
}

TEST(ReceiverFrequencySubstitution, GalileoTakesTheNearestGpsFrequency) {
  const AntennaCalibration rx = gpsOnlyReceiver();
  const auto e1 = receiverFrequencyCalibration(rx, GnssSystem::Galileo, 1, ReceiverFrequencySubstitution::Gps);
  const auto e5a = receiverFrequencyCalibration(rx, GnssSystem::Galileo, 5, ReceiverFrequencySubstitution::Gps);
  const auto e5b = receiverFrequencyCalibration(rx, GnssSystem::Galileo, 7, ReceiverFrequencySubstitution::Gps);
  ASSERT_NE(e1.calibration, nullptr);
  ASSERT_NE(e5a.calibration, nullptr);
  ASSERT_NE(e5b.calibration, nullptr);
  EXPECT_TRUE(e1.substituted);
  EXPECT_TRUE(e5a.substituted);
  EXPECT_EQ(e1.calibration, rx.frequency(GnssSystem::GPS, 1));
  EXPECT_EQ(e1.calibration->pco_m, Eigen::Vector3d(0.0011, -0.0002, 0.0914));
  // No G05 in the block: E5a falls back to G02 (L2).
  EXPECT_EQ(e5a.calibration, rx.frequency(GnssSystem::GPS, 2));
  EXPECT_EQ(e5a.calibration->pco_m, Eigen::Vector3d(-0.0003, 0.0004, 0.1198));
  EXPECT_EQ(e5b.calibration, rx.frequency(GnssSystem::GPS, 2));
  // GLONASS as the igs14.atx header says: G01 for R01, G02 for R02.
  EXPECT_EQ(receiverFrequencyCalibration(rx, GnssSystem::GLONASS, 2, ReceiverFrequencySubstitution::Gps).calibration,
            rx.frequency(GnssSystem::GPS, 2));
}

TEST(ReceiverFrequencySubstitution, E5aPrefersG05WhenCalibrated) {
  AntennaCalibration rx = gpsOnlyReceiver();
  rx.frequencies.push_back(gpsFrequency(5, 0.0005, 0.0001, 0.1250));
  const auto e5a = receiverFrequencyCalibration(rx, GnssSystem::Galileo, 5, ReceiverFrequencySubstitution::Gps);
  ASSERT_NE(e5a.calibration, nullptr);
  EXPECT_EQ(e5a.calibration->frequency, 5);  // same carrier, 1176.45 MHz
}

TEST(ReceiverFrequencySubstitution, NoneLeavesTheFrequencyMissing) {
  const AntennaCalibration rx = gpsOnlyReceiver();
  for (const int f : {1, 5}) {
    const auto l = receiverFrequencyCalibration(rx, GnssSystem::Galileo, f, ReceiverFrequencySubstitution::None);
    EXPECT_EQ(l.calibration, nullptr) << "E0" << f;
    EXPECT_FALSE(l.substituted);
  }
}

TEST(ReceiverFrequencySubstitution, OwnCalibrationWinsAndGpsIsNeverSubstituted) {
  AntennaCalibration rx = gpsOnlyReceiver();
  FrequencyCalibration e1;
  e1.system = GnssSystem::Galileo;
  e1.frequency = 1;
  e1.pco_m = Eigen::Vector3d(0.0, 0.0, 0.0901);
  rx.frequencies.push_back(e1);
  const auto own = receiverFrequencyCalibration(rx, GnssSystem::Galileo, 1, ReceiverFrequencySubstitution::Gps);
  ASSERT_NE(own.calibration, nullptr);
  EXPECT_FALSE(own.substituted);
  EXPECT_EQ(own.calibration->system, GnssSystem::Galileo);
  // A GPS frequency the block lacks (G05) stays missing: the table is for other systems.
  EXPECT_EQ(receiverFrequencyCalibration(rx, GnssSystem::GPS, 5, ReceiverFrequencySubstitution::Gps).calibration,
            nullptr);
  // A frequency without a row (GLONASS CDMA R04) stays missing.
  EXPECT_EQ(receiverFrequencyCalibration(rx, GnssSystem::GLONASS, 4, ReceiverFrequencySubstitution::Gps).calibration,
            nullptr);
}

// Every row's preferred stand-in is the GPS frequency nearest in carrier
// frequency (L1 1575.42, L2 1227.60, L5 1176.45 MHz, IS-GPS-200 / IS-GPS-705),
// and its fallback the nearest of L1/L2 (the two every calibration holds).
TEST(ReceiverFrequencySubstitution, TableRowsAreTheNearestGpsCarriers) {
  const auto nearest = [](double mhz, std::initializer_list<std::pair<int, double>> gps) {
    int best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& [f, carrier] : gps)
      if (std::abs(carrier - mhz) < best_d) best_d = std::abs(carrier - mhz), best = f;
    return best;
  };
  for (const GpsStandIn& row : gpsStandInTable()) {
    EXPECT_NE(row.system, GnssSystem::GPS);
    EXPECT_EQ(gpsStandIn(row.system, row.frequency), &row);
    EXPECT_EQ(row.gps_frequencies[0], nearest(row.carrier_mhz, {{1, 1575.42}, {2, 1227.60}, {5, 1176.45}}))
        << row.signal;
    const int l1_l2 = nearest(row.carrier_mhz, {{1, 1575.42}, {2, 1227.60}});
    EXPECT_TRUE(row.gps_frequencies[0] == l1_l2 || row.gps_frequencies[1] == l1_l2) << row.signal;
  }
  EXPECT_EQ(gpsStandIn(GnssSystem::GPS, 1), nullptr);
}

TEST(ReceiverFrequencySubstitution, NoteNamesAntennaSystemAndSignals) {
  const AntennaCalibration rx = gpsOnlyReceiver();
  const auto e1 = receiverFrequencyCalibration(rx, GnssSystem::Galileo, 1, ReceiverFrequencySubstitution::Gps);
  const auto e5a = receiverFrequencyCalibration(rx, GnssSystem::Galileo, 5, ReceiverFrequencySubstitution::Gps);
  EXPECT_EQ(receiverSubstitutionNote(rx, GnssSystem::Galileo, 1, e1, 5, e5a),
            "receiver antenna ASH701945E_M SCIS: no Galileo calibration, GPS L1/L2 values used for E1/E5a "
            "(measurement_model.corrections.receiver_frequency_substitution: gps)");
}

}  // namespace
}  // namespace ppp
