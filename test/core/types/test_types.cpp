// Satellite ids, observation codes, carrier frequencies and frames.
#include <gtest/gtest.h>

#include <cmath>

#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"

using namespace ppp;

TEST(SatelliteId, ParsesRinexForms) {
  EXPECT_EQ(SatelliteId::parse("G05")->toString(), "G05");
  EXPECT_EQ(SatelliteId::parse("G 5")->prn, 5);
  EXPECT_EQ(SatelliteId::parse(" 7")->system, GnssSystem::GPS);  // RINEX 2 blank = GPS
  EXPECT_EQ(SatelliteId::parse("R21")->system, GnssSystem::GLONASS);
  EXPECT_EQ(SatelliteId::parse("E36")->system, GnssSystem::Galileo);
  EXPECT_EQ(SatelliteId::parse("C59")->system, GnssSystem::BeiDou);
  EXPECT_EQ(SatelliteId::parse("J02")->system, GnssSystem::QZSS);
  EXPECT_EQ(SatelliteId::parse("S23")->system, GnssSystem::SBAS);
  EXPECT_FALSE(SatelliteId::parse("X01"));
  EXPECT_FALSE(SatelliteId::parse("G00"));
  EXPECT_FALSE(SatelliteId::parse("G33"));
  EXPECT_FALSE(SatelliteId::parse("G1a"));
  EXPECT_FALSE(SatelliteId::parse(""));
  EXPECT_LT(*SatelliteId::parse("G32"), *SatelliteId::parse("R01"));
}

TEST(ObservationCode, ParsesAndPrints) {
  const auto c = ObservationCode::parse("L2W");
  ASSERT_TRUE(c);
  EXPECT_EQ(c->type, ObservableType::CarrierPhase);
  EXPECT_EQ(c->band, '2');
  EXPECT_EQ(c->attribute, 'W');
  EXPECT_EQ(c->toString(), "L2W");
  EXPECT_EQ(c->signal(), "2W");
  EXPECT_FALSE(ObservationCode::parse("Q1C"));
  EXPECT_FALSE(ObservationCode::parse("C0C"));
  EXPECT_FALSE(ObservationCode::parse("C1CX"));
}

TEST(CarrierFrequency, PublishedValues) {
  // IS-GPS-200: L1 = 154 * 10.23 MHz, L2 = 120 * 10.23 MHz; IS-GPS-705: L5 = 115 * 10.23 MHz.
  EXPECT_DOUBLE_EQ(*carrierFrequency_hz(GnssSystem::GPS, '1'), 154 * 10.23e6);
  EXPECT_DOUBLE_EQ(*carrierFrequency_hz(GnssSystem::GPS, '2'), 120 * 10.23e6);
  EXPECT_DOUBLE_EQ(*carrierFrequency_hz(GnssSystem::GPS, '5'), 115 * 10.23e6);
  EXPECT_NEAR(*carrierWavelength_m(GnssSystem::GPS, '1'), 0.19029367, 1e-8);
  EXPECT_DOUBLE_EQ(*carrierFrequency_hz(GnssSystem::Galileo, '7'), 118 * 10.23e6);
  // GLONASS k = -7 on G1: 1602 - 7 * 0.5625 = 1598.0625 MHz (GLONASS ICD 5.1 table 3.1).
  EXPECT_DOUBLE_EQ(*carrierFrequency_hz(GnssSystem::GLONASS, '1', -7), 1598.0625e6);
  EXPECT_FALSE(carrierFrequency_hz(GnssSystem::GLONASS, '1'));  // needs the channel
  EXPECT_FALSE(carrierFrequency_hz(GnssSystem::GPS, '7'));
}

TEST(GlonassChannels, RangeChecked) {
  GlonassChannels ch;
  EXPECT_TRUE(ch.set(1, 1));
  EXPECT_FALSE(ch.set(31, 0));
  EXPECT_FALSE(ch.set(2, 14));
  EXPECT_EQ(ch.channel(1), 1);
  EXPECT_FALSE(ch.channel(2));
  EXPECT_EQ(ch.size(), 1);
}

TEST(GlonassChannels, FillMissingKeepsTheKnownChannels) {
  GlonassChannels header, nav;
  header.set(1, 1);
  nav.set(1, 6);
  nav.set(3, -4);
  header.fillMissing(nav);
  EXPECT_EQ(header.channel(1), 1);  // the header's entry stays
  EXPECT_EQ(header.channel(3), -4);
  EXPECT_EQ(header.size(), 2);
}

TEST(GlonassChannels, HeaderFirstThenTheConfiguredChannels) {
  GlonassChannels header, configured;
  header.set(5, 1);
  configured.set(5, 2);
  configured.set(7, 5);
  const GlonassChannels used = channelsHeaderFirst(header, configured);
  EXPECT_EQ(used.channel(5), 1);  // the header's
  EXPECT_EQ(used.channel(7), 5);  // the configuration's where the header has none
  EXPECT_FALSE(used.channel(9));
  EXPECT_EQ(header.channel(7), std::nullopt) << "the inputs stay as they are";
}

TEST(Frames, GeodeticRoundTripAtZimmerwald) {
  // ZIM2 truth (dataset README). Zimmerwald is at about 46.877 N, 7.465 E, 956 m
  // (IGS site log: 46 52 37.5 N, 7 27 54.4 E, ellipsoidal height 956.4 m).
  const Eigen::Vector3d p(4331299.5841, 567537.7070, 4633133.9645);
  const Geodetic g = ecefToGeodetic(p);
  EXPECT_NEAR(g.latitude_rad * kRadToDeg, 46.877, 0.001);
  EXPECT_NEAR(g.longitude_rad * kRadToDeg, 7.465, 0.001);
  EXPECT_NEAR(g.height_m, 956.4, 0.5);
  EXPECT_LT((geodeticToEcef(g) - p).norm(), 1e-6);
}

TEST(Frames, EnuAxesAndElevation) {
  const Eigen::Vector3d origin(4331299.5841, 567537.7070, 4633133.9645);
  const Geodetic g = ecefToGeodetic(origin);
  const Eigen::Matrix3d R = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  // A point 100 m straight up along the ellipsoid normal is at ENU (0, 0, 100).
  const Eigen::Vector3d up = geodeticToEcef({g.latitude_rad, g.longitude_rad, g.height_m + 100.0});
  EXPECT_LT((ecefToEnu(up, origin) - Eigen::Vector3d(0, 0, 100)).norm(), 1e-6);
  EXPECT_NEAR(azimuthElevation(origin, up).elevation_rad, kPi / 2, 1e-6);
  const Eigen::Vector3d east = enuToEcef(Eigen::Vector3d(1000, 0, 0), origin);
  const auto ae = azimuthElevation(origin, east);
  EXPECT_NEAR(ae.azimuth_rad, kPi / 2, 1e-9);
  EXPECT_NEAR(ae.elevation_rad, 0.0, 1e-9);
}
