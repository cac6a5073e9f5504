#pragma once
// SmoothedTrajectoryProvider: what an estimator that smooths (PppSmoother) offers
// beyond its filtered epoch results: the trajectory re-estimated with all data so
// far. Users reach it through PppEstimator::smoothing() (nullptr for a filter),
// never by casting to a concrete estimator.
#include <cstdint>
#include <functional>
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

/// The smoothed solution of all the data of a run (finalSmoothedSolution).
struct SmoothedSolution {
  std::vector<SmoothedEpoch> trajectory;  // every solved epoch it holds, in time order
  /// An arc's phase bias [m] in the solution; nullopt for an arc it does not hold.
  /// Valid while the estimator that gave it lives.
  std::function<std::optional<double>(const SatelliteId&, ArcId)> bias_m;
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
  /// After a run: the trajectory and the arcs' biases smoothed with all the data.
  /// A full smoother: its current estimate (smoothedTrajectory, smoothedBias_m). A
  /// fixed-lag smoother that keeps its whole graph (PppSmootherOptions::record_graph):
  /// the batch solve of every factor, i.e. the full smoother's solution; without it,
  /// its current estimate (states past the lag at their lag-boundary estimate).
  virtual SmoothedSolution finalSmoothedSolution() const = 0;
};

}  // namespace ppp
