#pragma once
// Writing replay bags: gnss/observations per epoch (GnssObservations) and
// gnss/corrections at the product rate (PreciseCorrections), from RINEX
// observations + SP3/CLK products (ppp_to_bag) or from a simulated flight.
// Correction batches are sampled from the products with PreciseEphemeris
// (orbits Lagrange-interpolated to the batch epochs, clocks exactly at their
// records), so a node replaying the bag sees the same products as ppp_solve.
// Bag times are the UTC header stamps; a batch is written 1 ms before an epoch
// at the same instant, so it arrives first. IMU readings, when given, go on
// imu/data (sensor_msgs/Imu) at their own stamps.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/models/correction_buffer.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace rosbag {
class Bag;
}

namespace ppp_ros {

struct BagWriteOptions {
  std::string observations_topic = "gnss/observations";
  std::string corrections_topic = "gnss/corrections";
  double correction_interval_s = 30.0;  // batch spacing (multiples of it in GPST)
  double margin_s = 60.0;               // batches this far before the first / after the last epoch
  std::optional<std::size_t> max_epochs;  // write only the first N epochs
  std::string orbit_source, clock_source, reference_frame, bias_set;  // product reference
  /// Satellite biases for integer ambiguity resolution consistent with the clocks
  /// (phase OSBs of the clocks' analysis centre, or the wide-lane biases of
  /// integer-recovery clocks): each batch carries their values at its epoch for
  /// the code and phase types of the observation header (PreciseCorrections
  /// ar_bias_source, satellites[].biases). nullptr: none (a node stays float).
  const ppp::BiasProvider* ar_biases = nullptr;
  std::uint8_t ar_bias_kind = 0;  // PreciseCorrections.ar_bias_kind of ar_biases (AR_BIASES_*)
  std::string antenna_model;      // PreciseCorrections.antenna_model ("" = not known)
  /// IMU readings (already screened: navigation/imu_input_screen.h), written on
  /// `imu_topic` as sensor_msgs/Imu in `imu_frame` (ros/imu_conversions.h), with
  /// the covariances of `imu_noise` at `imu_rate_hz` when given. None: no IMU topic.
  std::vector<ppp::ImuSample> imu;
  std::string imu_topic = "imu/data";
  std::string imu_frame = "imu_link";
  std::optional<ppp::ImuNoise> imu_noise;
  double imu_rate_hz = 0.0;
  /// Called with the open bag after the last message (extra topics, e.g. a truth path).
  std::function<void(rosbag::Bag&)> before_close;
};

struct BagWriteSummary {
  std::size_t epochs = 0, batches = 0, imu_readings = 0;
  std::optional<ppp::GnssTime> first, last;
  std::size_t frames = 0;          // writeUbxBag: UBX frames written
  std::string stream_problems;     // writeUbxBag: the framer's problems (StreamCounters::problemLines), "" if none
};

/// Correction batches at multiples of the interval in [first - margin, last + margin]
/// where the products give a value (satellites without one are left out of the batch).
std::vector<ppp::CorrectionBatch> sampleCorrections(const ppp::PreciseEphemeris& products, const ppp::GnssTime& first,
                                                   const ppp::GnssTime& last, const BagWriteOptions& options);

/// Pulls epochs from `next` (returns false at the end) and writes the bag.
/// Throws rosbag::BagException when the file cannot be written.
BagWriteSummary writeReplayBag(const std::string& path, const ppp::RinexObsHeader& header,
                               const std::function<bool(ppp::ObsEpoch&)>& next,
                               const ppp::PreciseEphemeris& products, const BagWriteOptions& options);

/// A u-blox UBX recording (RXM-RAWX observations, RXM-SFRBX navigation data, and
/// whatever else it holds) as a bag for the live input (ros.live, doc/live_input.md):
/// every UBX frame, unchanged, as one ppp_bayes_tree/GnssStreamBytes (format "ubx",
/// frame_id `ubx_frame`) on `ubx_topic`, in the recording's order. A frame is stamped
/// (header and bag time) when it was read at the receiver: at the receiver time of the
/// newest RXM-RAWX epoch (GPST into UTC) plus 1 us, plus 1 ns per frame after it (frames
/// before the first RXM-RAWX at its time), so that the IMU readings of `options.imu`
/// (options.imu_topic, at their own stamps) up to an epoch come before it. `summary.epochs`
/// counts the RXM-RAWX frames. Throws std::runtime_error when no RXM-RAWX has a time.
struct UbxBagOptions {
  std::string ubx_topic = "gnss/receiver";
  std::string ubx_frame = "gnss";
};
BagWriteSummary writeUbxBag(const std::string& path, const std::vector<std::uint8_t>& ubx_bytes,
                            const UbxBagOptions& ubx, const BagWriteOptions& options);

/// Topic of the simulated truth: nav_msgs/Path of the true antenna positions in
/// the `earth` frame (ECEF), latched, stamped at the first epoch.
inline constexpr const char* kTruthPathTopic = "truth/path";

/// A simulated flight as a replay bag: its observation epochs, correction
/// batches sampled from its products-with-error (flight.products, what an
/// estimator must use) and its truth path. The product reference fields of
/// `options` that are empty are filled with the simulator's (orbit and clock
/// intervals, IGS20); `ar_biases` unset: the flight's satellite phase OSBs when it
/// draws them (errors.ambiguity.satellite_phase_biases); `imu` unset: the flight's
/// IMU readings when it has them (imu.enabled), with the grade's covariances. `callerid` names the
/// writing program in the truth connection header.
BagWriteSummary writeSimulatedFlightBag(const std::string& path, const ppp::SimulatedFlight& flight,
                                        BagWriteOptions options, const std::string& callerid);

}  // namespace ppp_ros
