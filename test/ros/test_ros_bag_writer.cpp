// Replay bags of simulated flights: writeSimulatedFlightBag (used by
// `ppp_to_bag --simulate` and `ppp_simulate --bag`) read back with rosbag; IMU
// readings on imu/data (sensor_msgs/Imu), from the library and from
// `ppp_to_bag --imu` on the u-blox walk's IMU (shared data), and an IMU file in g
// refused by the input screen; a UBX recording as a bag of the live input
// (writeUbxBag, `ppp_to_bag --ubx` on the walk).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nav_msgs/Path.h>
#include <sensor_msgs/Imu.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "ppp_bayes_tree/GnssStreamBytes.h"
#include "ppp_bayes_tree/io/imu/imu_file_loader.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/io/ubx/ubx_nav_encoder.h"
#include "ppp_bayes_tree/ros/bag_writer.h"
#include "ppp_bayes_tree/ros/imu_conversions.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;

struct BagContents {
  std::vector<ppp_bayes_tree::GnssObservations> observations;
  std::vector<ppp_bayes_tree::PreciseCorrections> corrections;
  std::vector<ros::Time> correction_bag_times, observation_bag_times;
  std::vector<nav_msgs::Path> truth;
  std::string truth_latching;
  std::vector<sensor_msgs::Imu> imu;
  std::vector<ros::Time> imu_bag_times;
};

BagContents readBag(const std::string& path) {
  BagContents c;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "gnss/observations") {
      c.observations.push_back(*m.instantiate<ppp_bayes_tree::GnssObservations>());
      c.observation_bag_times.push_back(m.getTime());
    } else if (m.getTopic() == "gnss/corrections") {
      c.corrections.push_back(*m.instantiate<ppp_bayes_tree::PreciseCorrections>());
      c.correction_bag_times.push_back(m.getTime());
    } else if (m.getTopic() == "imu/data") {
      c.imu.push_back(*m.instantiate<sensor_msgs::Imu>());
      c.imu_bag_times.push_back(m.getTime());
    } else if (m.getTopic() == ppp_ros::kTruthPathTopic) {
      c.truth.push_back(*m.instantiate<nav_msgs::Path>());
      const auto h = m.getConnectionHeader();
      const auto it = h->find("latching");
      c.truth_latching = it == h->end() ? "" : it->second;
    }
  }
  return c;
}

ppp::SimulatedFlight shortFlight() {
  ppp::SimulationConfig config;
  config.profile = ppp::FlightProfile::Loiter;
  config.duration_s = 150.0;
  return ppp::simulateFlight(config, 11);
}

std::string tempBag(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("ppp_bag_writer_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

}  // namespace

TEST(SimulatedFlightBag, HoldsEveryEpochTheProductsWithErrorAndTheTruthPath) {
  const ppp::SimulatedFlight f = shortFlight();
  const std::string path = tempBag("flight.bag");
  const auto summary = ppp_ros::writeSimulatedFlightBag(path, f, {}, "/test");
  const BagContents c = readBag(path);

  // Every observation epoch, in order, losslessly.
  ASSERT_EQ(summary.epochs, f.epochs.size());
  ASSERT_EQ(c.observations.size(), f.epochs.size());
  ppp::RinexObsHeader layout;
  for (std::size_t k = 0; k < f.epochs.size(); k += 37) {
    ppp::ObsEpoch back;
    ppp_ros::ConversionIssues issues;
    ppp_ros::fromMessage(c.observations[k], layout, back, issues);
    EXPECT_EQ(issues.total(), 0u);
    EXPECT_EQ(back.time, f.epochs[k].time);
    EXPECT_EQ(back.satellites.size(), f.epochs[k].satellites.size());
    EXPECT_EQ(c.observation_bag_times[k], ppp_ros::utcStamp(f.epochs[k].time));
  }
  // header.seq numbers each topic's messages as a live publisher does (rosbag play keeps
  // it): the nodes count the messages lost on the way from its gaps.
  for (std::size_t k = 0; k < c.observations.size(); ++k) ASSERT_EQ(c.observations[k].header.seq, k);
  for (std::size_t b = 0; b < c.corrections.size(); ++b) ASSERT_EQ(c.corrections[b].header.seq, b);

  // Batches every 30 s over [first - 60 s, last + 60 s], each written just before
  // the epoch at its instant; values are the products WITH error (what an
  // estimator must use), not the truth the observations were made with.
  ASSERT_EQ(c.corrections.size(), summary.batches);
  const double span_s = f.epochs.back().time - f.epochs.front().time;
  EXPECT_GE(c.corrections.size(), std::size_t(span_s / 30.0) + 4);
  double max_truth_difference_m = 0.0;
  for (std::size_t b = 0; b < c.corrections.size(); ++b) {
    ppp_ros::ConversionIssues issues;
    const ppp::CorrectionBatch batch = ppp_ros::fromMessage(c.corrections[b], issues);
    EXPECT_EQ(issues.total(), 0u);
    EXPECT_EQ(batch.time.wholeSeconds() % 30, 0);
    EXPECT_EQ(c.correction_bag_times[b], ppp_ros::utcStamp(batch.time) - ros::Duration(0.001));
    EXPECT_EQ(batch.reference_frame, "IGS20");
    EXPECT_NE(batch.orbit_source.find("simulated SP3"), std::string::npos);
    ASSERT_FALSE(batch.satellites.empty());
    for (const auto& s : batch.satellites) {
      const auto orbit = f.products.orbit(s.satellite, batch.time);
      const auto truth = f.truth_products.orbit(s.satellite, batch.time);
      ASSERT_TRUE(orbit.ok() && s.position_ecef_m);
      EXPECT_NEAR((*s.position_ecef_m - orbit.value->position_ecef_m).norm(), 0.0, 1e-6);
      if (truth.ok())
        max_truth_difference_m =
            std::max(max_truth_difference_m, (*s.position_ecef_m - truth.value->position_ecef_m).norm());
    }
  }
  EXPECT_GT(max_truth_difference_m, 1e-3) << "the bag must carry the products with error";

  // A flight without an IMU (the default) has no IMU topic.
  EXPECT_TRUE(c.imu.empty());
  EXPECT_EQ(summary.imu_readings, 0u);

  // One latched truth path with every truth epoch, in the earth (ECEF) frame.
  ASSERT_EQ(c.truth.size(), 1u);
  EXPECT_EQ(c.truth_latching, "1");
  EXPECT_EQ(c.truth[0].header.frame_id, "earth");
  ASSERT_EQ(c.truth[0].poses.size(), f.truth.size());
  for (std::size_t k = 0; k < f.truth.size(); k += 50) {
    const auto& p = c.truth[0].poses[k].pose.position;
    EXPECT_DOUBLE_EQ(p.x, f.truth[k].trajectory.position_ecef_m.x());
    EXPECT_DOUBLE_EQ(p.y, f.truth[k].trajectory.position_ecef_m.y());
    EXPECT_DOUBLE_EQ(p.z, f.truth[k].trajectory.position_ecef_m.z());
  }
  fs::remove_all(fs::path(path).parent_path());
}

TEST(SimulatedFlightBag, PppSimulateBagWritesTheSameBagAsTheLibrary) {
  // `ppp_simulate --bag` (catkin build) and the library call give the same messages.
  const std::string dir = fs::path(tempBag("x")).parent_path().string();
  const std::string cli_bag = dir + "/cli.bag", lib_bag = dir + "/lib.bag";
  const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_simulate --profile loiter --duration-min 2.5 --seed 11 --bag " +
                          cli_bag + " > " + dir + "/cli.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  ppp_ros::writeSimulatedFlightBag(lib_bag, shortFlight(), {}, "/ppp_simulate");
  const BagContents a = readBag(cli_bag), b = readBag(lib_bag);
  ASSERT_EQ(a.observations.size(), b.observations.size());
  ASSERT_EQ(a.corrections.size(), b.corrections.size());
  ASSERT_EQ(a.truth.size(), 1u);
  EXPECT_EQ(a.truth[0].poses.size(), b.truth[0].poses.size());
  for (std::size_t k = 0; k < a.observations.size(); ++k) {
    ASSERT_EQ(a.observations[k].satellites.size(), b.observations[k].satellites.size()) << k;
    EXPECT_EQ(a.observations[k].header.stamp, b.observations[k].header.stamp);
  }
  fs::remove_all(dir);
}

TEST(ImuBag, ReadingsGoOnImuDataAsSensorMsgsImu) {
  const ppp::SimulatedFlight f = shortFlight();
  ppp_ros::BagWriteOptions o;
  const ppp::ImuNoise noise = ppp::imuNoisePreset(ppp::ImuGrade::IndustrialMems);
  for (int k = 0; k < 400; ++k) {  // 2 s at 200 Hz from the first epoch
    ppp::ImuSample s;
    s.time = f.epochs.front().time + 0.005 * k;
    s.specific_force_mps2 = Eigen::Vector3d(0.1 * k, -0.2, -9.81);
    s.angular_rate_radps = Eigen::Vector3d(1e-3, 2e-3 * k, -3e-3);
    o.imu.push_back(s);
  }
  o.imu_frame = "imu_link";
  o.imu_noise = noise;
  o.imu_rate_hz = 200.0;
  const std::string path = tempBag("imu.bag");
  const auto summary = ppp_ros::writeSimulatedFlightBag(path, f, o, "/test");
  EXPECT_EQ(summary.imu_readings, 400u);
  const BagContents c = readBag(path);
  ASSERT_EQ(c.imu.size(), 400u);
  for (std::size_t k = 0; k < c.imu.size(); ++k) {
    const sensor_msgs::Imu& m = c.imu[k];
    ASSERT_EQ(m.header.seq, k);
    EXPECT_EQ(m.header.frame_id, "imu_link");
    EXPECT_EQ(c.imu_bag_times[k], ppp_ros::utcStamp(o.imu[k].time));  // UTC, as the other topics
    EXPECT_EQ(m.orientation_covariance[0], -1.0);                      // REP 145: no orientation
    const ppp::ImuSample back = ppp_ros::fromImuMessage(m);
    EXPECT_NEAR(back.time - o.imu[k].time, 0.0, 1e-9);
    EXPECT_EQ(back.specific_force_mps2, o.imu[k].specific_force_mps2);
    EXPECT_EQ(back.angular_rate_radps, o.imu[k].angular_rate_radps);
  }
  // The covariance of one reading: density^2 * rate on the diagonal.
  const double d = noise.gyro_noise_density_radps_per_sqrthz;
  EXPECT_DOUBLE_EQ(c.imu[0].angular_velocity_covariance[4], d * d * 200.0);
  EXPECT_EQ(c.imu[0].angular_velocity_covariance[1], 0.0);
  fs::remove_all(fs::path(path).parent_path());
}

TEST(ImuBag, PppToBagWritesTheScreenedReadingsOfTheWalk) {
  if (!ppp::test::sharedDataAvailable()) GTEST_SKIP() << "no shared data";
  const std::string csv = ppp::test::dataPath("streams/ubx/imu_1730.csv");
  const std::string tag = csv + ".tag";
  const std::string dir = fs::path(tempBag("x")).parent_path().string();
  const std::string bag = dir + "/walk_imu.bag";
  const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_to_bag --simulate loiter --duration-min 1 --imu " + csv +
                          " --imu-tag " + tag + " --out " + bag + " > " + dir + "/walk.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  // The library's loading of the same files (reader, then the input screen).
  ppp::ImuFileOptions file;
  file.path = csv;
  file.tag_path = tag;
  file.format = ppp::ImuFileFormat::RtklibLogged;
  const std::vector<ppp::ImuSample> kept = ppp::loadImuFile(file).samples;
  ASSERT_GT(kept.size(), 20000u);  // 20,455 readings over 134 s (data README)
  const BagContents c = readBag(bag);
  ASSERT_EQ(c.imu.size(), kept.size());
  for (std::size_t k = 0; k < kept.size(); k += 997) {
    const ppp::ImuSample back = ppp_ros::fromImuMessage(c.imu[k]);
    EXPECT_NEAR(back.time - kept[k].time, 0.0, 1e-9) << k;
    EXPECT_EQ(back.specific_force_mps2, kept[k].specific_force_mps2) << k;
  }
  // At rest at the start, in m/s^2: the walk's accelerometers read about 1 g.
  EXPECT_NEAR(ppp_ros::fromImuMessage(c.imu[0]).specific_force_mps2.norm(), 9.9, 0.3);
  std::ifstream log(dir + "/walk.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find(std::to_string(kept.size()) + " IMU readings on imu/data"), std::string::npos) << text;
  fs::remove_all(dir);
}

TEST(ImuBag, PppToBagRefusesAnImuFileInG) {
  const std::string dir = fs::path(tempBag("x")).parent_path().string();
  const std::string csv = dir + "/imu_in_g.csv", bag = dir + "/g.bag";
  {
    std::ofstream out(csv);
    out << "# gps_week,seconds_of_week,fx,fy,fz,wx,wy,wz\n";
    for (int k = 0; k < 200; ++k)  // at rest, in g where m/s^2 is expected
      out << "2111," << 345600.0 + 0.01 * k << ",0.01,-0.02,-1.0,0.0,0.0,0.0\n";
  }
  const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_to_bag --simulate loiter --duration-min 1 --imu " + csv +
                          " --out " + bag + " > " + dir + "/g.log 2>&1";
  EXPECT_NE(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream log(dir + "/g.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("accelerations in g, not m/s^2"), std::string::npos) << text;
  EXPECT_NE(text.find("no IMU reading left after the input screen"), std::string::npos) << text;
  EXPECT_NE(text.find(csv), std::string::npos) << text;  // the file is named
  fs::remove_all(dir);
}

TEST(ImuBag, ASimulatedFlightWithAnImuCarriesItsReadings) {
  ppp::SimulationConfig config;
  config.profile = ppp::FlightProfile::Loiter;
  config.duration_s = 20.0;
  config.imu.enabled = true;
  config.imu.rate_hz = 100.0;
  const ppp::SimulatedFlight f = ppp::simulateFlight(config, 11);
  ASSERT_FALSE(f.imu.samples.empty());
  const std::string path = tempBag("flight_imu.bag");
  const auto summary = ppp_ros::writeSimulatedFlightBag(path, f, {}, "/test");
  EXPECT_EQ(summary.imu_readings, f.imu.samples.size());
  const BagContents c = readBag(path);
  ASSERT_EQ(c.imu.size(), f.imu.samples.size());
  for (std::size_t k = 0; k < c.imu.size(); k += 101) {
    const ppp::ImuSample back = ppp_ros::fromImuMessage(c.imu[k]);
    EXPECT_NEAR(back.time - f.imu.samples[k].time, 0.0, 1e-9);
    EXPECT_EQ(back.angular_rate_radps, f.imu.samples[k].angular_rate_radps);
  }
  const double d = f.imu.noise.accel_noise_density_mps2_per_sqrthz;
  EXPECT_DOUBLE_EQ(c.imu[0].linear_acceleration_covariance[8], d * d * 100.0);
  fs::remove_all(fs::path(path).parent_path());
}

namespace {

/// The stream messages of a bag in the bag's order, with their bag times, and where the
/// IMU readings fall among them (each entry: the topic).
struct UbxBagContents {
  std::vector<ppp_bayes_tree::GnssStreamBytes> frames;
  std::vector<ros::Time> frame_bag_times;
  std::vector<sensor_msgs::Imu> imu;
  std::vector<std::string> order;
};

UbxBagContents readUbxBag(const std::string& path) {
  UbxBagContents c;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    c.order.push_back(m.getTopic());
    if (auto f = m.instantiate<ppp_bayes_tree::GnssStreamBytes>()) {
      c.frames.push_back(*f);
      c.frame_bag_times.push_back(m.getTime());
    } else if (auto i = m.instantiate<sensor_msgs::Imu>()) {
      c.imu.push_back(*i);
    }
  }
  return c;
}

std::vector<std::uint8_t> concat(const std::vector<ppp::UbxFrameBytes>& frames) {
  std::vector<std::uint8_t> out;
  for (const auto& f : frames) out.insert(out.end(), f.begin(), f.end());
  return out;
}

}  // namespace

TEST(UbxBag, EveryFrameUnchangedInOrderStampedAtItsEpochAfterTheImuReadingsUpToIt) {
  // A navigation frame before the first epoch, two epochs 0.25 s apart with a frame after each.
  const ppp::GnssTime t0 = ppp::GnssTime::fromGpsWeek(2381, 408639.748);
  const ppp::UbxFrameBytes nav = ppp::encodeUbxFrame(0x02, 0x13, std::vector<std::uint8_t>(16, 7));
  const std::vector<ppp::UbxFrameBytes> frames = {nav, ppp::encodeRawxTime(t0), nav, ppp::encodeRawxTime(t0 + 0.25),
                                                  nav};
  std::vector<std::uint8_t> bytes = concat(frames);
  bytes[nav.size() - 1] ^= 0xFF;  // the first frame's checksum broken: that frame is lost, counted
  const std::vector<std::uint8_t> clean = concat(frames);
  ppp_ros::BagWriteOptions o;
  for (int k = -10; k <= 40; ++k) {  // readings every 10 ms, one exactly at each epoch
    ppp::ImuSample r;
    r.time = t0 + 0.01 * k;
    r.specific_force_mps2 = Eigen::Vector3d(0.0, 0.0, 9.81);
    o.imu.push_back(r);
  }
  const std::string path = tempBag("ubx.bag");
  const ppp_ros::BagWriteSummary s = ppp_ros::writeUbxBag(path, clean, ppp_ros::UbxBagOptions{}, o);
  EXPECT_EQ(s.epochs, 2u);
  EXPECT_EQ(s.frames, frames.size());
  EXPECT_TRUE(s.stream_problems.empty()) << s.stream_problems;
  const UbxBagContents c = readUbxBag(path);
  ASSERT_EQ(c.frames.size(), frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(c.frames[k].data, frames[k]) << k;
    EXPECT_EQ(c.frames[k].format, "ubx");
    EXPECT_EQ(c.frames[k].header.seq, k);
    EXPECT_EQ(c.frames[k].header.stamp, c.frame_bag_times[k]);
    if (k > 0) EXPECT_GT(c.frame_bag_times[k], c.frame_bag_times[k - 1]) << k;
  }
  // Stamped at the epoch read (+1 us); the frame before the first epoch just before it.
  EXPECT_NEAR((c.frame_bag_times[1] - ppp_ros::utcStamp(t0)).toSec(), 1e-6, 1e-9);
  EXPECT_NEAR((c.frame_bag_times[3] - ppp_ros::utcStamp(t0 + 0.25)).toSec(), 1e-6, 1e-9);
  EXPECT_LT(c.frame_bag_times[0], c.frame_bag_times[1]);
  // In the bag's order the readings up to each epoch (the one at it included) come before it.
  std::size_t readings_before = 0, frames_seen = 0;
  for (const std::string& topic : c.order) {
    if (topic == "imu/data") ++readings_before;
    else if (++frames_seen == 2) EXPECT_EQ(readings_before, 11u);  // t0 - 0.1 .. t0
    else if (frames_seen == 4) EXPECT_EQ(readings_before, 36u);    // .. t0 + 0.25
  }
  EXPECT_EQ(c.imu.size(), o.imu.size());

  // A damaged stream: the frames the framer finds, its problems said.
  const ppp_ros::BagWriteSummary damaged = ppp_ros::writeUbxBag(path, bytes, ppp_ros::UbxBagOptions{}, {});
  EXPECT_EQ(damaged.frames, frames.size() - 1);
  EXPECT_FALSE(damaged.stream_problems.empty());
  // No epoch at all: refused.
  EXPECT_THROW(ppp_ros::writeUbxBag(path, nav, ppp_ros::UbxBagOptions{}, {}), std::runtime_error);
  fs::remove_all(fs::path(path).parent_path());
}

TEST(UbxBag, PppToBagWritesTheWalkWithItsImu) {
  if (!ppp::test::sharedDataAvailable()) GTEST_SKIP() << "no shared data";
  const std::string ubx = ppp::test::dataPath("streams/ubx/gnss_1730.ubx");
  const std::string csv = ppp::test::dataPath("streams/ubx/imu_1730.csv");
  const std::string dir = fs::path(tempBag("x")).parent_path().string();
  const std::string bag = dir + "/walk.bag";
  const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_to_bag --ubx " + ubx + " --imu " + csv + " --imu-tag " +
                          csv + ".tag --out " + bag + " > " + dir + "/walk.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const UbxBagContents c = readUbxBag(bag);
  std::size_t rawx = 0, sfrbx = 0;
  for (const auto& f : c.frames) {
    rawx += f.data[2] == 0x02 && f.data[3] == 0x15;
    sfrbx += f.data[2] == 0x02 && f.data[3] == 0x13;
  }
  EXPECT_EQ(rawx, 536u);   // shared/data README: 536 RXM-RAWX epochs, 2,328 RXM-SFRBX
  EXPECT_EQ(sfrbx, 2328u);
  EXPECT_GT(c.imu.size(), 20000u);
  std::ifstream log(dir + "/walk.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("(536 RXM-RAWX epochs)"), std::string::npos) << text;
  // --ubx is a form of its own.
  const std::string both = std::string(PPP_BIN_DIR) + "/ppp_to_bag --ubx " + ubx + " --simulate loiter --out " + bag +
                           " > " + dir + "/both.log 2>&1";
  EXPECT_NE(std::system(both.c_str()), 0);
  fs::remove_all(dir);
}
