#pragma once
// SmoothedTrajectoryProvider: what an estimator that smooths (PppSmoother) offers
// beyond its filtered epoch results: the trajectory re-estimated with all data so
// far. Users reach it through EpochEstimator::smoothing() (nullptr for a filter),
// never by casting to a concrete estimator.
#include <cstdint>
#include <optional>
#include <vector>

#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_result.h"
#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"

namespace ppp {

/// One state of the smoothed trajectory.
struct SmoothedEpoch {
  GnssTime time;
  std::uint32_t index = 0;  // x<index>
  ReceiverState state;
  /// Marginal covariance when asked for and the state is still in the graph.
  std::optional<ReceiverCovariance> covariance;
};

class SmoothedTrajectoryProvider {
 public:
  virtual ~SmoothedTrajectoryProvider() = default;
  /// Every solved epoch's state from the current estimate (all data so far).
  virtual std::vector<SmoothedEpoch> smoothedTrajectory(bool with_covariance = false) const = 0;
  /// The newest state at or before `time` (see PppSmoother::smoothedEpochAt).
  virtual std::optional<SmoothedEpoch> smoothedEpochAt(const GnssTime& time, bool with_covariance = false) const = 0;
  /// The smoothing window [s]; 0: all data (full smoother).
  virtual double fixedLag_s() const = 0;
  /// Current estimate of an arc's bias while it is in the graph.
  virtual std::optional<double> smoothedBias_m(const SatelliteId& satellite, ArcId arc) const = 0;
};

}  // namespace ppp
