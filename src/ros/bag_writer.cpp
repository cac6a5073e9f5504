#include "ppp_bayes_tree/ros/bag_writer.h"

#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Path.h>
#include <rosbag/bag.h>

#include "ppp_bayes_tree/GnssStreamBytes.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/ros/imu_conversions.h"
#include "ppp_bayes_tree/ros/message_conversions.h"

namespace ppp_ros {
namespace {

/// The options' IMU readings on their topic, header.seq numbering them (0, 1, ...).
void writeImuReadings(rosbag::Bag& bag, const BagWriteOptions& o) {
  std::uint32_t imu_seq = 0;
  for (const ppp::ImuSample& reading : o.imu) {
    sensor_msgs::Imu m = toImuMessage(reading, o.imu_frame, o.imu_noise, o.imu_rate_hz);
    m.header.seq = imu_seq++;
    bag.write(o.imu_topic, m.header.stamp, m);
  }
}

}  // namespace

std::vector<ppp::CorrectionBatch> sampleCorrections(const ppp::PreciseEphemeris& products, const ppp::GnssTime& first,
                                                   const ppp::GnssTime& last, const BagWriteOptions& o) {
  std::vector<ppp::CorrectionBatch> out;
  const auto step = static_cast<std::int64_t>(std::llround(o.correction_interval_s));
  if (step <= 0) return out;
  std::set<ppp::SatelliteId> sats = products.orbitSatellites();
  for (const auto& s : products.clockSatellites()) sats.insert(s);
  const std::int64_t from = (first - o.margin_s).wholeSeconds(), to = (last + o.margin_s).wholeSeconds() + 1;
  for (std::int64_t t_s = (from + step - 1) / step * step; t_s <= to; t_s += step) {
    const ppp::GnssTime t = ppp::GnssTime::fromGpsSeconds(t_s);
    ppp::CorrectionBatch b;
    b.time = t;
    b.orbit_source = o.orbit_source;
    b.clock_source = o.clock_source;
    b.reference_frame = o.reference_frame;
    b.bias_set = o.bias_set;
    for (const auto& sat : sats) {
      const auto orbit = products.orbit(sat, t);
      const auto clock = products.clock(sat, t);
      if (!orbit.ok() && !clock.ok()) continue;
      ppp::SatelliteCorrection c;
      c.satellite = sat;
      if (orbit.ok()) {
        c.position_ecef_m = orbit.value->position_ecef_m;
        c.velocity_ecef_mps = orbit.value->velocity_ecef_mps;
      }
      if (clock.ok()) {
        c.clock_bias_s = clock.value->clock_bias_s;
        c.clock_drift_s_per_s = clock.value->clock_drift_s_per_s;
      }
      b.satellites.push_back(c);
    }
    if (!b.satellites.empty()) out.push_back(std::move(b));
  }
  return out;
}

BagWriteSummary writeReplayBag(const std::string& path, const ppp::RinexObsHeader& header,
                               const std::function<bool(ppp::ObsEpoch&)>& next, const ppp::PreciseEphemeris& products,
                               const BagWriteOptions& o) {
  // Epochs first (converted now: they are small), then the batches over their span.
  std::vector<ppp_bayes_tree::GnssObservations> epochs;
  ppp::ObsEpoch e;
  BagWriteSummary summary;
  while ((!o.max_epochs || epochs.size() < *o.max_epochs) && next(e)) {
    if (e.flag != ppp::EpochFlag::Ok && e.flag != ppp::EpochFlag::PowerFailure) continue;
    if (!summary.first) summary.first = e.time;
    summary.last = e.time;
    epochs.push_back(toMessage(e, header));
  }
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  std::vector<ppp::CorrectionBatch> batches;
  if (summary.first) batches = sampleCorrections(products, *summary.first, *summary.last, o);
  // header.seq numbers each topic's messages (0, 1, ...) as a live roscpp publisher does:
  // rosbag play keeps the recorded seq, and the nodes count messages lost on the way
  // from its gaps (ros.input.observation_queue_size in config/ppp.yaml).
  std::size_t k = 0;
  std::uint32_t obs_seq = 0;
  const auto writeBatch = [&](std::size_t i) {
    auto c = toMessage(batches[i]);
    if (o.ar_biases) {
      std::vector<ppp::SatelliteId> sats;
      for (const auto& sc : batches[i].satellites) sats.push_back(sc.satellite);
      addBiases(c, ppp::sampleBiases(*o.ar_biases, batches[i].time, header, sats));
      c.ar_bias_kind = o.ar_bias_kind;
    }
    c.antenna_model = o.antenna_model;
    c.header.seq = static_cast<std::uint32_t>(i);
    bag.write(o.corrections_topic, c.header.stamp - ros::Duration(0.001), c);
  };
  for (auto& m : epochs) {
    for (; k < batches.size() && utcStamp(batches[k].time) <= m.header.stamp; ++k) writeBatch(k);
    m.header.seq = obs_seq++;
    bag.write(o.observations_topic, m.header.stamp, m);
  }
  for (; k < batches.size(); ++k) writeBatch(k);
  writeImuReadings(bag, o);
  summary.imu_readings = o.imu.size();
  if (o.before_close) o.before_close(bag);
  bag.close();
  summary.epochs = epochs.size();
  summary.batches = batches.size();
  return summary;
}

namespace {

/// The receiver time (GPST) of an RXM-RAWX payload: rcvTow (R8 at 0) and week (U2 at 8);
/// nullopt for a payload too short or a time that is no time of week.
std::optional<ppp::GnssTime> rawxTime(const std::vector<std::uint8_t>& payload) {
  if (payload.size() < 16) return std::nullopt;
  std::uint64_t bits = 0;
  for (int i = 7; i >= 0; --i) bits = bits << 8 | payload[static_cast<std::size_t>(i)];
  double tow_s = 0.0;
  std::memcpy(&tow_s, &bits, sizeof tow_s);
  const int week = payload[8] | payload[9] << 8;
  if (!(tow_s >= 0.0 && tow_s < 604800.0)) return std::nullopt;
  return ppp::GnssTime::fromGpsWeek(week, tow_s);
}

/// The UBX frames of `bytes` with the receiver time each was read at (UbxBagOptions).
std::vector<std::pair<ppp::UbxFrame, ros::Time>> stampedUbxFrames(const std::vector<std::uint8_t>& bytes,
                                                                 BagWriteSummary* summary) {
  std::vector<std::pair<ppp::UbxFrame, ros::Time>> frames;
  std::optional<ros::Time> epoch_stamp;
  std::size_t before_first = 0, since_epoch = 0;
  ppp::UbxFramer framer;
  framer.feed(bytes.data(), bytes.size(), [&](const ppp::UbxFrame& f) {
    const bool rawx = f.message_class == 0x02 && f.message_id == 0x15;
    const std::optional<ppp::GnssTime> t = rawx ? rawxTime(f.payload) : std::nullopt;
    if (t) {
      epoch_stamp = utcStamp(*t) + ros::Duration(1e-6);
      since_epoch = 0;
      ++summary->epochs;
    }
    if (!epoch_stamp) ++before_first;
    frames.emplace_back(f, epoch_stamp ? *epoch_stamp + ros::Duration(0, static_cast<std::int32_t>(since_epoch++))
                                       : ros::Time());
  });
  framer.finish();
  if (framer.counters().totalProblems() > 0) summary->stream_problems = framer.counters().problemLines();
  if (!epoch_stamp) throw std::runtime_error("no RXM-RAWX frame with a receiver time in the UBX recording");
  // Frames before the first epoch: read at its time, in their order, just before it.
  const ros::Time first = frames[before_first].second;
  for (std::size_t k = 0; k < before_first; ++k)
    frames[k].second = first - ros::Duration(0, static_cast<std::int32_t>(before_first - k));
  return frames;
}

/// The frame's bytes as the receiver sent them (sync, class, id, length, payload, checksum).
std::vector<std::uint8_t> ubxFrameBytes(const std::vector<std::uint8_t>& bytes, const ppp::UbxFrame& f) {
  const auto begin = bytes.begin() + static_cast<std::ptrdiff_t>(f.byte_offset);
  return std::vector<std::uint8_t>(begin, begin + static_cast<std::ptrdiff_t>(f.payload.size() + 8));
}

}  // namespace

BagWriteSummary writeUbxBag(const std::string& path, const std::vector<std::uint8_t>& bytes, const UbxBagOptions& ubx,
                            const BagWriteOptions& o) {
  BagWriteSummary summary;
  const auto frames = stampedUbxFrames(bytes, &summary);
  summary.frames = frames.size();
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  std::uint32_t seq = 0;
  for (const auto& [frame, stamp] : frames) {
    ppp_bayes_tree::GnssStreamBytes m;
    m.header.seq = seq++;
    m.header.stamp = stamp;
    m.header.frame_id = ubx.ubx_frame;
    m.format = "ubx";
    m.data = ubxFrameBytes(bytes, frame);
    bag.write(ubx.ubx_topic, stamp, m);
  }
  writeImuReadings(bag, o);
  summary.imu_readings = o.imu.size();
  bag.close();
  summary.first = fromUtcStamp(frames.front().second);
  summary.last = fromUtcStamp(frames.back().second);
  return summary;
}

namespace {

/// truth/path (earth frame, latched) at the first epoch's stamp.
void writeTruthPath(rosbag::Bag& bag, const ppp::SimulatedFlight& f, const std::string& callerid) {
  if (f.truth.empty()) return;
  nav_msgs::Path path;
  path.header.frame_id = "earth";
  path.header.stamp = utcStamp(f.truth.front().trajectory.time);
  for (const auto& e : f.truth) {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = "earth";
    p.header.stamp = utcStamp(e.trajectory.time);
    p.pose.position.x = e.trajectory.position_ecef_m.x();
    p.pose.position.y = e.trajectory.position_ecef_m.y();
    p.pose.position.z = e.trajectory.position_ecef_m.z();
    p.pose.orientation.w = 1.0;
    path.poses.push_back(p);
  }
  // A connection header of our own must carry the whole connection description.
  auto header = boost::make_shared<ros::M_string>();
  (*header)["topic"] = kTruthPathTopic;
  (*header)["type"] = ros::message_traits::datatype(path);
  (*header)["md5sum"] = ros::message_traits::md5sum(path);
  (*header)["message_definition"] = ros::message_traits::definition(path);
  (*header)["callerid"] = callerid;
  (*header)["latching"] = "1";  // rosbag play re-publishes it latched
  bag.write(kTruthPathTopic, path.header.stamp, path, header);
}

}  // namespace

BagWriteSummary writeSimulatedFlightBag(const std::string& path, const ppp::SimulatedFlight& flight,
                                        BagWriteOptions options, const std::string& callerid) {
  const auto& c = flight.config;
  if (options.orbit_source.empty())
    options.orbit_source = "simulated SP3 (" + std::to_string(int(c.orbit_interval_s)) + " s, interpolated)";
  if (options.clock_source.empty())
    options.clock_source = "simulated CLK (" + std::to_string(int(c.clock_interval_s)) + " s)";
  if (options.reference_frame.empty()) options.reference_frame = "IGS20";
  // The flight's satellite phase OSBs (errors.ambiguity.satellite_phase_biases), consistent with its clocks.
  if (!options.ar_biases && !flight.phase_biases.empty()) {
    options.ar_biases = &flight.phase_biases;
    options.ar_bias_kind = ppp_bayes_tree::PreciseCorrections::AR_BIASES_ANALYSIS_CENTRE_OSB;
  }
  // The flight's IMU readings (config.imu.enabled), unless readings are given.
  if (options.imu.empty() && !flight.imu.samples.empty()) {
    options.imu = flight.imu.samples;
    options.imu_noise = flight.imu.noise;
    options.imu_rate_hz = c.imu.rate_hz;
  }
  auto user_before_close = options.before_close;
  options.before_close = [&](rosbag::Bag& bag) {
    writeTruthPath(bag, flight, callerid);
    if (user_before_close) user_before_close(bag);
  };
  std::size_t k = 0;
  return writeReplayBag(path, flight.header, [&](ppp::ObsEpoch& e) {
    if (k >= flight.epochs.size()) return false;
    e = flight.epochs[k++];
    return true;
  }, flight.products, options);
}

}  // namespace ppp_ros
