#pragma once
// EpochEstimator: the estimator step of the offline PPP pipeline. The pipeline
// does everything up to the linearised measurements (reading, signal selection,
// arc tracking, the measurement model) and hands each epoch to an estimator
// through this interface, so that the EKF (EkfEstimator) and the smoother plug
// into the same pipeline and are fed identical epochs.
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/arc_tracker.h"
#include "ppp_bayes_tree/ppp/ekf_ppp.h"
#include "ppp_bayes_tree/ppp/measurement_function.h"
#include "ppp_bayes_tree/ppp/ppp_config.h"
#include "ppp_bayes_tree/ppp/ppp_smoother.h"

namespace ppp {

/// One epoch's result of any estimator (same content as the EKF's: status,
/// solution, used and rejected satellites with reasons, residuals).
using EstimatorEpochResult = EkfEpochResult;

/// What the pipeline gives an estimator for one epoch.
struct EstimatorEpochInput {
  GnssTime time;
  /// Linearises this epoch's measurements at any receiver state (the single model).
  const MeasurementFunction* evaluate = nullptr;
  /// The usable dual-frequency observations and their arc ids (same order).
  const std::vector<DualFrequencyObservation>* observations = nullptr;
  const std::vector<ArcId>* arcs = nullptr;
  /// Arcs that ended at this epoch (slip, gap) before this epoch's new arcs start.
  const std::vector<EndedArc>* ended_arcs = nullptr;
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
};

/// The forward EKF-PPP (EkfPpp) as an EpochEstimator: ended arcs lose their bias.
class EkfEstimator : public EpochEstimator {
 public:
  explicit EkfEstimator(const PppConfig& config);
  std::string name() const override { return "ekf"; }
  void setApproximatePosition(const Eigen::Vector3d& position_ecef_m) override {
    ekf_.setApproximatePosition(position_ecef_m);
  }
  EstimatorEpochResult processEpoch(const EstimatorEpochInput& input) override;
  void arcsEnded(const std::vector<EndedArc>& ended) override;
  const EkfPpp& filter() const { return ekf_; }

 private:
  EkfPpp ekf_;
};

/// The PPP smoother (PppSmoother) as an EpochEstimator. processEpoch returns the
/// FILTERED solution (final for the newest state at that time); after the run,
/// smoother().smoothedTrajectory() gives the SMOOTHED solution of every solved
/// epoch, and lastResult() the smoother's own per-epoch diagnostics (variables
/// relinearized / re-eliminated, update time, new biases).
class SmootherEstimator : public EpochEstimator {
 public:
  explicit SmootherEstimator(const PppConfig& config);
  std::string name() const override { return "smoother"; }
  void setApproximatePosition(const Eigen::Vector3d& position_ecef_m) override {
    smoother_.setApproximatePosition(position_ecef_m);
  }
  EstimatorEpochResult processEpoch(const EstimatorEpochInput& input) override;
  void arcsEnded(const std::vector<EndedArc>& ended) override;
  const PppSmoother& smoother() const { return smoother_; }
  PppSmoother& smoother() { return smoother_; }
  const SmootherEpochResult& lastResult() const { return last_; }

 private:
  PppSmoother smoother_;
  SmootherEpochResult last_;
};

/// The smoother's epoch result in the common form (diagnostics beyond it dropped).
EstimatorEpochResult toEstimatorEpochResult(const SmootherEpochResult& r);

/// Estimators by name: "ekf", "smoother" (others: nullptr, with `why` saying so).
std::unique_ptr<EpochEstimator> makeEstimator(const std::string& name, const PppConfig& config, std::string* why);

}  // namespace ppp
