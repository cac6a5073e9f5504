#pragma once
// EpochEstimator: the estimator step of the offline PPP pipeline. The pipeline
// does everything up to the linearised measurements (reading, signal selection,
// arc tracking, the measurement model) and hands each epoch to an estimator
// through this interface, so that the EKF (EkfEstimator) and the smoother plug
// into the same pipeline and are fed identical epochs. Both run the same epoch
// front end (PppEstimatorBase); what only a smoother offers is reached through
// smoothing() (nullptr for a filter), its per-epoch diagnostics through the
// result's `smoother` part.
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/estimators/ekf_ppp.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_options.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_estimator_base.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"
#include "ppp_bayes_tree/ppp/estimators/smoothed_trajectory_provider.h"
#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/ppp/model/measurement_function.h"

namespace ppp {

/// What the pipeline gives an estimator for one epoch.
struct EstimatorEpochInput {
  GnssTime time;
  /// Linearises this epoch's measurements at any receiver state (the single model).
  const MeasurementFunction* evaluate = nullptr;
  /// The start model (PppMeasurementModel::evaluateStart) for a start without an
  /// approximate position (PppEstimatorBase::processEpoch); nullable.
  const MeasurementFunction* evaluate_start = nullptr;
  /// The usable dual-frequency observations and their arc ids (same order).
  const std::vector<DualFrequencyObservation>* observations = nullptr;
  const std::vector<ArcId>* arcs = nullptr;
  /// Arcs that ended at this epoch (slip, gap) before this epoch's new arcs start.
  const std::vector<EndedArc>* ended_arcs = nullptr;
  /// Satellite phase OSBs consistent with the clocks (phase_bias_consistency.h);
  /// nullptr when the products allow no integer ambiguities (float).
  const BiasProvider* phase_biases = nullptr;
};

class EpochEstimator {
 public:
  virtual ~EpochEstimator() = default;
  /// Short name used in output file names ("ekf", "smoother").
  virtual std::string name() const = 0;
  /// Sets the starting point (RINEX APPROX POSITION XYZ) before the first epoch.
  virtual void setApproximatePosition(const Eigen::Vector3d& position_ecef_m) = 0;
  /// Processes one epoch in time order; the result is final for a filter.
  virtual EstimatorEpochResult processEpoch(const EstimatorEpochInput& input) = 0;
  /// Arcs that ended without a replacement (end of data).
  virtual void arcsEnded(const std::vector<EndedArc>& ended) = 0;
  /// The estimator behind: state layout, active arcs, restarts after failures.
  virtual const PppEstimatorBase& core() const = 0;
  /// The smoothed trajectory of an estimator that smooths; nullptr for a filter.
  virtual const SmoothedTrajectoryProvider* smoothing() const { return nullptr; }
  /// The last epoch's result, with its ambiguity summary.
  virtual const EstimatorEpochResult& lastResult() const = 0;
};

/// The forward EKF-PPP (EkfPpp) as an EpochEstimator: ended arcs lose their bias.
class EkfEstimator : public EpochEstimator {
 public:
  explicit EkfEstimator(const EstimatorOptions& options);
  std::string name() const override { return "ekf"; }
  void setApproximatePosition(const Eigen::Vector3d& position_ecef_m) override {
    ekf_.setApproximatePosition(position_ecef_m);
  }
  EstimatorEpochResult processEpoch(const EstimatorEpochInput& input) override;
  void arcsEnded(const std::vector<EndedArc>& ended) override;
  const PppEstimatorBase& core() const override { return ekf_; }
  const EkfPpp& filter() const { return ekf_; }
  const EstimatorEpochResult& lastResult() const override { return last_; }
  void resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& r);
  /// The resolver (e.g. to hold an integer restored after a restart).
  AmbiguityResolver& resolver() { return ambiguity_; }

 private:
  EkfPpp ekf_;
  AmbiguityResolver ambiguity_;  // PPP-AR on a copy of the filter state
  EstimatorEpochResult last_;
};

/// The PPP smoother (PppSmoother) as an EpochEstimator. processEpoch returns the
/// FILTERED solution (final for the newest state at that time) with the smoother's
/// own diagnostics (variables relinearized / re-eliminated, update time, new
/// biases); after the run, smoothing()->smoothedTrajectory() gives the SMOOTHED
/// solution of every solved epoch.
class SmootherEstimator : public EpochEstimator {
 public:
  explicit SmootherEstimator(const EstimatorOptions& options);
  std::string name() const override { return "smoother"; }
  void setApproximatePosition(const Eigen::Vector3d& position_ecef_m) override {
    smoother_.setApproximatePosition(position_ecef_m);
  }
  EstimatorEpochResult processEpoch(const EstimatorEpochInput& input) override;
  void arcsEnded(const std::vector<EndedArc>& ended) override;
  const PppEstimatorBase& core() const override { return smoother_; }
  const SmoothedTrajectoryProvider* smoothing() const override { return &smoother_; }
  const PppSmoother& smoother() const { return smoother_; }
  PppSmoother& smoother() { return smoother_; }
  const EstimatorEpochResult& lastResult() const override { return last_; }
  /// PPP-AR (when enabled): the EKF's decision path, AmbiguityResolver::resolveAndHold,
  /// on the smoother's float joint (PppSmoother::floatJoint: root clique, held
  /// fixes taken out); the held integers are held in the graph and one released
  /// as wrong is removed, both in one update (PppSmoother::updateFixes). The
  /// result's solution is then the filtered
  /// solution with the fixes; FIXED when the resolver holds at least
  /// narrow_lane.min_fixed integers (as the EKF).
  void resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& r);
  /// The resolver (e.g. to hold an integer restored after a restart).
  AmbiguityResolver& resolver() { return ambiguity_; }

 private:
  PppSmoother smoother_;
  AmbiguityResolver ambiguity_;
  EstimatorEpochResult last_;
};

/// Estimators by name, as registered in estimator_registry.h (others: nullptr,
/// with `why` saying so).
std::unique_ptr<EpochEstimator> makeEstimator(const std::string& name, const EstimatorOptions& options, std::string* why);

}  // namespace ppp
