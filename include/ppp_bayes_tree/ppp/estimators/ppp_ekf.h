#pragma once
// PppEkf: the reference extended Kalman filter for kinematic PPP.
//
// State: the receiver state in its layout (receiver_state_layout.h: position
// ECEF [m], zenith wet delay [m], one receiver clock [m] per processed system),
// then one ionosphere-free phase bias [m] per active arc (dynamic dimension).
// The epoch front end (PppEstimator: code least-squares start, clock shifts,
// arc bookkeeping, prefit screening, new-arc bias values, residual records,
// ended arcs) is shared with the smoother; the EKF's own steps are:
//  1. predict over the real elapsed time dt (StochasticModel: random-walk
//     position/ZWD, white clocks, constant biases);
//  2. add a bias for each new arc at the front end's initial value, a priori
//     sigma from the StochasticModel;
//  3. iterated measurement update with code and phase rows, Joseph form,
//     re-linearising through the MeasurementFunction; optional postfit check;
//  4. finite-value and positive-definiteness checks of x and P (P symmetrised).
// PPP-AR (resolveAmbiguities): the filter stays float; the fixed solution is a
// copy of it constrained on the integers validated across epochs and held, read
// through the core's seam (the biases start at coreDim()).
// Too few satellites -> status NoSolution (no estimate, filter untouched: the
// next epoch predicts over the real elapsed time). A numerical failure -> status
// Failed with the reason, filter left as it was before the epoch.
#include <Eigen/Core>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"
#include "ppp_bayes_tree/ppp/estimators/ekf_options.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_result.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_options.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_estimator.h"
#include "ppp_bayes_tree/ppp/model/measurement_function.h"
#include "ppp_bayes_tree/ppp/model/stochastic_model.h"

namespace ppp {

class PppEkf : public PppEstimator {
 public:
  explicit PppEkf(StochasticModel model = {}, EkfOptions options = {}, CodeLeastSquaresOptions start_options = {},
                  ReceiverStateLayout layout = {});
  /// From the estimator options (the registry's factory, estimator_registry.h).
  explicit PppEkf(const EstimatorOptions& options);

  std::string name() const override { return "ekf"; }

  /// Initialise explicitly at `state` with the a priori sigmas (no biases).
  /// Otherwise processEpoch initialises from the code least squares.
  void initialise(const GnssTime& time, const ReceiverState& state);

  bool initialised() const { return initialised_; }
  std::optional<GnssTime> lastTime() const { return initialised_ ? std::optional<GnssTime>(last_time_) : std::nullopt; }
  ReceiverState receiverState() const;
  ReceiverCovariance receiverCovariance() const;
  int activeBiasCount() const { return static_cast<int>(f_.biases.size()); }
  std::vector<ArcId> activeArcs() const override;
  std::optional<double> biasEstimate_m(ArcId arc) const override;
  std::optional<double> biasSigma_m(ArcId arc) const;
  /// Full state and covariance (receiver part first, then biases in activeArcs() order).
  const Eigen::VectorXd& stateVector() const { return f_.x; }
  const Eigen::MatrixXd& covarianceMatrix() const { return f_.P; }

  /// The covariance the prediction over dt_s would give (filter unchanged).
  Eigen::MatrixXd predictedCovariance(double dt_s) const;

  const EkfOptions& options() const { return options_; }

 protected:
  bool hasState() const override { return initialised_; }
  std::optional<GnssTime> lastSolvedTime() const override { return lastTime(); }
  bool startsAt(const GnssTime& time) const override { return fresh_ && time == last_time_; }
  ReceiverState predict(double dt_s, bool first, const std::optional<ReceiverState>& start) override;
  std::optional<ArcBiasPrior> predictedBias(ArcId arc) const override;
  bool solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) override;
  void arcRemoved(ArcId arc) override;
  int biasCount() const override { return activeBiasCount(); }
  void resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& result) override;

  struct BiasSlot {
    ArcId arc = 0;
    SatelliteId satellite;
  };
  struct Filter {  // everything an epoch may change (committed only with a solution)
    Eigen::VectorXd x;
    Eigen::MatrixXd P;
    std::vector<BiasSlot> biases;
  };

  // The seam of a filter whose states before the phase biases (its core) are
  // not the receiver state itself (the GNSS/INS filter, ppp_ins_ekf.h). The
  // defaults are the EKF's: the core is the receiver state in its layout.
  /// Number of states before the phase biases.
  virtual int coreDim() const { return layout_.dim(); }
  /// State index of a receiver-layout index other than the position.
  virtual int coreIndex(int receiver_index) const { return receiver_index; }
  int clockIndex(GnssSystem system) const { return coreIndex(layout_.clock(system)); }
  /// The receiver state (the measurement model's point) at the filter state x.
  virtual ReceiverState receiverStateAt(const Eigen::VectorXd& x) const;
  /// The covariance of receiverStateAt(x) from the filter covariance P.
  virtual ReceiverCovariance receiverCovarianceAt(const Eigen::VectorXd& x, const Eigen::MatrixXd& P) const;
  /// A measurement's Jacobian (over the receiver layout) as a row over the core at x.
  virtual Eigen::RowVectorXd coreJacobian(const SatelliteMeasurement& m, const Eigen::VectorXd& x) const;
  /// The filter of a start at `state` (a priori sigmas, no biases).
  virtual Filter initialFilter(const ReceiverState& state) const;
  /// Adds the process noise over dt_s (nothing when `first`).
  virtual void predictFilter(Filter& f, double dt_s, bool first) const;
  /// The process noise over dt_s of the states other than the position (zenith
  /// wet delay, gradients, white clocks, phase biases).
  void predictDelaysClocksBiases(Filter& f, double dt_s) const;
  /// Last step of an update before it is committed (e.g. a closed-loop reset).
  virtual void closeLoop(Filter& /*f*/) {}
  /// The fixed copy of this epoch's filter (PPP-AR), after the solution was read
  /// from it (receiverStateAt); the float filter is not changed.
  virtual void fixedSolutionFound(const AmbiguityFixedState& /*fixed*/) {}

  static void removeBias(Filter& f, std::size_t slot, int receiver_dim);
  static int findBias(const Filter& f, ArcId arc);

  bool initialised_ = false;
  bool fresh_ = false;  // initialised, no epoch processed yet
  GnssTime last_time_;
  Filter f_;
  Filter work_;  // the prediction of the epoch being processed

 private:
  struct Row;
  struct Attempt;
  enum class UpdateStep { Done, Restart, Failed };

  // The steps of solve() (numbered there).
  Filter shiftedPrediction(const EpochSolveInput& in) const;
  std::vector<Row> updateRows(const EpochSolveInput& in, const std::set<SatelliteId>& excluded, Filter& fa) const;
  UpdateStep iterateUpdate(const EpochSolveInput& in, Attempt& a, std::set<SatelliteId>& excluded,
                           EstimatorEpochResult& result) const;
  bool relinearise(const EpochSolveInput& in, Attempt& a, std::set<SatelliteId>& excluded,
                   EstimatorEpochResult& result) const;
  void linearSystem(Attempt& a, double code_variance_factor) const;
  bool kalmanGain(Attempt& a, EstimatorEpochResult& result) const;
  bool josephCovariance(Attempt& a, EstimatorEpochResult& result) const;
  bool postfitRejects(Attempt& a, std::set<SatelliteId>& excluded, EstimatorEpochResult& result) const;
  void commitUpdate(const EpochSolveInput& in, Attempt a, EpochSolveOutput& out);

  EkfOptions options_;
};

}  // namespace ppp
