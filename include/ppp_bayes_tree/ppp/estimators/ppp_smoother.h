#pragma once
// PppSmoother: kinematic PPP as an incremental factor graph (iSAM2 on the Bayes
// tree), with the same interface as PppEkf so that a pipeline can run either.
// One state per solved epoch (position, ZWD, clocks) and one IF phase bias per
// arc, linked by random-walk and prior factors; IF code and phase factors from
// the SAME MeasurementFunction and sigmas as the EKF (ppp_factors.h). Each epoch
// runs the shared front end (PppEstimator), then ONE iSAM2 update, the
// postfit check and the filtered marginals of the new state. The smoothed
// output re-reads every state from the current estimate; with fixed_lag_s > 0
// older states are marginalized. Held integer ambiguities enter the graph as
// factors (integer_ambiguity_factor.h). A marginalized-state sink bounds the
// memory of live runs.
// The graph, the steps of an epoch, restarts, ambiguity resolution and live use
// in detail: doc/estimators.md, "The smoother".
//
// References: Kaess M. et al. (2012) iSAM2: Incremental smoothing and mapping
// using the Bayes tree, Int. J. Robotics Research 31(2); Watson R.M., Gross J.N.
// (2018) Evaluation of kinematic precise point positioning convergence with an
// incremental graph optimizer, IEEE/ION PLANS (arXiv:1804.04197).
#include <Eigen/Core>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_result.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_options.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_estimator.h"
#include "ppp_bayes_tree/ppp/estimators/smoothed_trajectory_provider.h"
#include "ppp_bayes_tree/ppp/estimators/smoother_options.h"
#include "ppp_bayes_tree/ppp/model/measurement_function.h"
#include "ppp_bayes_tree/ppp/model/stochastic_model.h"
#include "ppp_bayes_tree/smoother/fixed_lag_smoother.h"
#include "ppp_bayes_tree/smoother/isam2.h"

namespace ppp {

class PppSmoother : public PppEstimator, public SmoothedTrajectoryProvider {
 public:
  explicit PppSmoother(StochasticModel model = {}, PppSmootherOptions options = {},
                       CodeLeastSquaresOptions start_options = {}, ReceiverStateLayout layout = {});
  /// From the estimator options (the registry's factory, estimator_registry.h).
  explicit PppSmoother(const EstimatorOptions& options);
  ~PppSmoother();
  PppSmoother(PppSmoother&&) noexcept;
  PppSmoother& operator=(PppSmoother&&) noexcept;

  std::string name() const override { return "smoother"; }

  /// Key symbols of the inertial variables of a state (a GNSS/INS smoother): its
  /// NavState and IMU bias at state index k are symbolKey(symbol, k).
  static constexpr char kNavStateSymbol = 'n';
  static constexpr char kImuBiasSymbol = 'i';
  const SmoothedTrajectoryProvider* smoothing() const override { return this; }

  bool initialised() const { return !states_.empty(); }
  std::optional<GnssTime> lastTime() const;
  /// Filtered state and covariance of the newest state (as of its update).
  ReceiverState receiverState() const;
  ReceiverCovariance receiverCovariance() const;
  int activeBiasCount() const { return static_cast<int>(arcs_.size()); }
  std::vector<ArcId> activeArcs() const override;
  /// Current (smoothed) estimate of an arc's bias while it is in the graph.
  std::optional<double> biasEstimate_m(ArcId arc) const override;
  /// Current (smoothed) estimate of any arc's bias still in the graph, active or
  /// ended (full smoother: every arc; fixed lag: the arcs inside the window).
  std::optional<double> biasEstimate_m(const SatelliteId& satellite, ArcId arc) const;

  /// The whole trajectory re-estimated with all data so far (fixed lag: states
  /// beyond the lag keep their estimate at the lag boundary).
  std::vector<SmoothedEpoch> smoothedTrajectory(bool with_covariance = false) const override;
  /// One state of the smoothed trajectory without re-reading all of them: the newest
  /// state at or before `time`, from the current estimate (all data so far), with its
  /// marginal covariance when asked for. With a fixed lag, a state already marginalized
  /// is replaced by the oldest state still in the window (the lag boundary), which may
  /// be after `time`. nullopt: no state yet, or every state is after `time`.
  /// Cost: O(log n) plus the marginal, which grows with the state's depth in the
  /// Bayes tree (the newest state is in the root clique: cheap).
  std::optional<SmoothedEpoch> smoothedEpochAt(const GnssTime& time, bool with_covariance = false) const override;
  double fixedLag_s() const override { return options_.fixed_lag_s; }
  std::optional<double> smoothedBias_m(const SatelliteId& satellite, ArcId arc) const override {
    return biasEstimate_m(satellite, arc);
  }
  SmoothedSolution finalSmoothedSolution() const override;

  const PppSmootherOptions& options() const { return options_; }
  const smoother::ISAM2& isam2() const;

  /// Receives a state leaving the smoother for good, with its final estimate (no covariance).
  using StateSink = std::function<void(const SmoothedEpoch&)>;
  /// Live use: states that leave the graph (marginalized past the lag, or left behind
  /// by a restart) go to `sink`, once each and in time order, and are dropped from
  /// memory (unless the graph is recorded, PppSmootherOptions::record_graph, which needs them all).
  /// From then on smoothedTrajectory() holds only the states not yet handed out.
  /// An empty sink restores the default (every state kept).
  void setMarginalizedStateSink(StateSink sink) { sink_ = std::move(sink); }
  /// End of a run: hands every state not yet handed out to the sink, with the
  /// current best estimate (a full back-substitution), oldest first. Returns the
  /// number handed out (0 without a sink). Further epochs may follow.
  std::size_t finishTrajectory();
  /// States held in memory (the window with a sink; every state without one).
  std::size_t storedStateCount() const { return states_.size(); }
  /// Biases whose last state is remembered (fixed lag: those in the graph).
  std::size_t storedBiasCount() const { return bias_last_state_.size(); }

  // Ambiguity resolution (the decision is the caller's AmbiguityResolver, as for
  // the EKF; resolveAmbiguities drives it). A fix is HELD in the graph as
  // IntegerAmbiguityFactors (integer_ambiguity_factor.h), so that iSAM2 carries it
  // into every state of the fixed arcs, before the fix epoch too.
  /// The filtered joint of the newest state and the biases observed at the last
  /// epoch (the root clique, read right after the update): x = [receiver state,
  /// biases of `arcs`] [m], P its covariance. What the resolver fixes on.
  struct FilteredJoint {
    Eigen::VectorXd x;
    Eigen::MatrixXd P;
    std::vector<ArcId> arcs;
  };
  const FilteredJoint& filteredJoint() const { return joint_; }
  /// The filtered solution of the newest state (after any fix added or removed).
  const EpochSolution& filteredSolution() const { return filtered_; }
  /// Adds the integer constraints A x = y (rows over filteredJoint()'s layout, zero
  /// on the receiver part; y [cycles]) as factors with sigma
  /// fixed_ambiguity_sigma_cycles, except the rows on the arcs of a fix already
  /// held (the resolver's held set is passed every epoch); one iSAM2 update;
  /// refreshes the filtered solution and joint. Returns the number of factors
  /// added; throws what the update throws.
  int holdIntegerConstraints(const Eigen::MatrixXd& A, const Eigen::VectorXd& y);
  /// releaseFixes(release) and holdIntegerConstraints(A, y) in ONE iSAM2 update
  /// (the removed factors' indices and the new factors together) and one refresh
  /// of the filtered solution: what the estimator does each epoch. A may have no
  /// rows. Returns the fixes removed and added; throws what the update throws.
  struct FixChanges {
    int removed = 0, added = 0;
  };
  FixChanges updateFixes(const std::vector<std::pair<ArcId, ArcId>>& release, const Eigen::MatrixXd& A,
                         const Eigen::VectorXd& y);
  /// The filtered joint WITHOUT the held fixes (the float solution of all data so
  /// far): the information of every held fix whose arcs are all in the joint is
  /// taken out exactly (fixes on arcs outside it stay in: they can no longer be
  /// separated from the marginal). What the resolver decides on, as the EKF's
  /// float state. nullopt: not separable numerically.
  std::optional<FilteredJoint> floatJoint() const;
  /// Removes the held fixes on these single differences (arc pairs, either order)
  /// from the graph (remove_factor_indices: a wrong fix released by the resolver),
  /// counted in fixesRemoved(); refreshes the filtered solution. Returns the number removed.
  int releaseFixes(const std::vector<std::pair<ArcId, ArcId>>& pairs);
  /// A fix held in the graph: its factor (an IntegerAmbiguityFactor), its index in
  /// the graph and the arcs of its bias keys (same order as the factor's
  /// coefficients); sorted_arcs: the same arcs sorted (the fix's identity).
  struct HeldFix {
    smoother::FactorIndex index = 0;
    std::vector<ArcId> arcs;
    smoother::NonlinearFactor::Ptr factor;
    std::vector<ArcId> sorted_arcs;
  };
  const std::vector<HeldFix>& heldFixes() const { return held_; }
  /// Fixes removed as wrong so far.
  std::size_t fixesRemoved() const { return fixes_removed_; }

  /// The MAP estimate of ALL recorded factors (every epoch, also those a fixed
  /// lag has marginalized) by a batch Gauss-Newton solve (batch_solver.h), started
  /// from the latest estimates: the full smoother's smoothed solution, computed
  /// once at the end. Keys: stateKey(index), biasKey(sat, arc) (ppp_factors.h).
  /// Throws std::logic_error without recording, and the batch solver's errors.
  smoother::Values batchSmoothedValues() const;
  /// The states held in `values` (e.g. batchSmoothedValues()) as a trajectory, in
  /// time order (no covariances; states missing from `values` are left out).
  std::vector<SmoothedEpoch> trajectoryFrom(const smoother::Values& values) const;

 protected:
  /// Relinearization thresholds of the inertial variables (position: relinearize_position_m).
  static constexpr double kRelinearizeAttitude_rad = 1e-3;
  static constexpr double kRelinearizeVelocity_mps = 0.01;
  static constexpr double kRelinearizeAccelBias_mps2 = 1e-3;
  static constexpr double kRelinearizeGyroBias_radps = 1e-5;

  // Seams of a smoother with more variables per state (PppInsSmoother); the defaults
  // add nothing.
  /// Sigma of the position random walk between two states over dt_s [m].
  virtual double positionProcessSigma_m(double dt_s) const;
  /// The new state's further variables and factors (step 1 of solve); `keys` gets the
  /// new variables, which are kept in the root clique with the state.
  virtual void addInertialFactors(const EpochSolveInput& /*in*/, std::uint32_t /*index*/,
                                  smoother::NonlinearFactorGraph& /*factors*/, smoother::Values& /*values*/,
                                  smoother::KeyVector& /*keys*/) const {}
  /// A restart from the last state `index` (recoverAfterFailure): priors on its
  /// further variables, added to the restart's factors, values and root keys.
  virtual void addRestartInertialFactors(std::uint32_t /*index*/, smoother::NonlinearFactorGraph& /*factors*/,
                                         smoother::Values& /*values*/, smoother::KeyVector& /*newest*/) const {}
  /// Index of the newest state (nullopt before the first).
  std::optional<std::uint32_t> newestStateIndex() const {
    return states_.empty() ? std::nullopt : std::optional<std::uint32_t>(states_.back().index);
  }

  bool hasState() const override { return initialised(); }
  std::optional<GnssTime> lastSolvedTime() const override { return lastTime(); }
  ReceiverState predict(double dt_s, bool first, const std::optional<ReceiverState>& start) override;
  std::optional<ArcBiasPrior> predictedBias(ArcId arc) const override;
  bool solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) override;
  bool recoverAfterFailure(EstimatorEpochResult& result) override;
  void arcRemoved(ArcId arc) override { arcs_.erase(arc); }
  int biasCount() const override { return activeBiasCount(); }
  /// PPP-AR (when enabled): the EKF's decision path, AmbiguityResolver::resolveAndHold,
  /// on the float joint (floatJoint: root clique, held fixes taken out); the held
  /// integers are held in the graph and one released as wrong is removed, both in
  /// one update (updateFixes). The result's solution is then the filtered solution
  /// with the fixes; FIXED when the resolver holds at least narrow_lane.min_fixed
  /// integers (as the EKF).
  void resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& result) override;
  void finishEpoch(EstimatorEpochResult& result) const override;

 private:
  /// resolveAmbiguities' decision on the float joint and its one graph update;
  /// true when fixes were added or removed.
  bool resolveOnFloatJoint(const EstimatorEpochInput& input, const EstimatorEpochResult& r,
                           AmbiguityFixSummary& summary);
  struct ArcSlot {
    SatelliteId satellite;
    smoother::Key key = 0;
    std::uint32_t last_state = 0;   // index of the last state it was observed at
    double filtered_m = 0.0;        // filtered estimate and variance after the last update
    double filtered_variance_m2 = 0.0;
  };
  struct StateRecord {
    GnssTime time;
    std::uint32_t index = 0;
    ReceiverState last_estimate;  // refreshed after each update while in the graph
  };

  /// The state carried between the steps of solve() (defined with them).
  struct SolveEpoch;
  void addStateFactors(SolveEpoch& e) const;
  void addMeasurementFactors(SolveEpoch& e) const;
  bool updateWithNewFactors(SolveEpoch& e, EstimatorEpochResult& result);
  bool postfitCheck(SolveEpoch& e, EstimatorEpochResult& result);
  bool removeSatellite(SolveEpoch& e, std::size_t k, EstimatorEpochResult& result);
  bool filteredMarginals(SolveEpoch& e, EstimatorEpochResult& result) const;
  void commitEpoch(SolveEpoch& e);
  void recordEpochGraph(const SolveEpoch& e);
  void forgetMarginalized(const smoother::Values& marginalized);
  std::vector<SolvedMeasurement> residualRows(const SolveEpoch& e) const;
  /// The noise of a code or phase factor (Huber kernel with options_.robust).
  smoother::NoiseModel::Ptr measurementNoise(double sigma) const;

  smoother::ISAM2Params isamParams() const;
  /// sqrt of a variance, floored so that a zero process noise stays a valid (stiff) sigma.
  static double sigmaOf(double variance_m2);

  /// A new, empty iSAM2 (or fixed-lag smoother).
  void newGraph();
  /// Before a restart: the old states keep the current estimate when it is still
  /// readable and finite (their smoothed values), else their last estimate.
  void keepReadableEstimates();
  /// Hands the oldest states no longer in the graph to the sink (with a sink).
  void releaseLeftStates();
  /// One update that adds and/or removes factors (no new variables), newest state
  /// and the last joint's biases in the root; returns the new factors' indices.
  std::vector<smoother::FactorIndex> updateGraph(const smoother::NonlinearFactorGraph& add,
                                                 const std::vector<smoother::FactorIndex>& remove);
  /// Re-reads the filtered joint, solution and the joint's bias slots.
  void refreshFiltered();
  /// Fixed-lag timestamp of a state [s] since the first state.
  double lagStamp_s(const GnssTime& time) const { return time - *time_origin_; }

  PppSmootherOptions options_;
  std::unique_ptr<smoother::ISAM2> isam_;              // full smoother
  std::unique_ptr<smoother::FixedLagSmoother> lag_;    // fixed-lag smoother
  std::deque<StateRecord> states_;   // oldest first; with a sink: the states not yet handed out
  std::optional<GnssTime> time_origin_;  // the first state's time (fixed-lag timestamps)
  StateSink sink_;
  std::optional<std::uint32_t> handed_out_through_;  // finishTrajectory(): states up to here are out
  std::map<ArcId, ArcSlot> arcs_;                      // the active set
  std::map<smoother::Key, std::uint32_t> bias_last_state_;  // every bias in the graph
  EpochSolution filtered_;
  FilteredJoint joint_;
  std::vector<HeldFix> held_;
  std::size_t fixes_removed_ = 0;
  smoother::NonlinearFactorGraph recorded_factors_;
  smoother::Values recorded_values_;  // initial values; refreshed from the estimate when solving
};

}  // namespace ppp
