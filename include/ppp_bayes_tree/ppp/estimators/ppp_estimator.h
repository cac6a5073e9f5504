#pragma once
// PppEstimator: the one interface of the PPP estimators and the epoch front end
// that the EKF (PppEkf) and the smoother (PppSmoother) share, so that both run
// the same sequence and see the same screened measurements; each estimator
// implements only its steps (predict, solve, ambiguity resolution), like a
// FilterBase with processMeasurement and the filter's own predict/correct.
// Estimators are made by name through the registry (estimator_registry.h).
// processEpoch(EstimatorEpochInput) is the pipeline's epoch: the ended arcs
// leave, the measurement epoch runs nine named steps (start or advance, predict,
// linearise, book the arcs, screen, initial biases, solve or recover, commit,
// consistency test), then PPP-AR when enabled. A failed or unsolved epoch leaves
// the estimator as it was before the epoch (or restarted, when estimator_reset
// is reported). The steps in detail: doc/estimators.md, "The epoch front end".
#include <Eigen/Core>
#include <chrono>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_input.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_result.h"
#include "ppp_bayes_tree/ppp/estimators/inertial_state.h"
#include "ppp_bayes_tree/ppp/estimators/smoothed_trajectory_provider.h"
#include "ppp_bayes_tree/ppp/model/measurement_function.h"
#include "ppp_bayes_tree/ppp/model/receiver_state_layout.h"
#include "ppp_bayes_tree/ppp/model/stochastic_model.h"
#include "ppp_bayes_tree/ppp/screening/postfit_screening.h"
#include "ppp_bayes_tree/ppp/screening/prefit_screening.h"
#include "ppp_bayes_tree/ppp/screening/screening_options.h"

namespace ppp {

class PppEstimator {
 public:
  virtual ~PppEstimator() = default;

  /// Short name used in output file names (the registry's name: "ekf", "smoother").
  virtual std::string name() const = 0;
  /// The pipeline's epoch, in time order: ended arcs, the measurement epoch, PPP-AR.
  /// The result is final for a filter; it is also kept as lastResult().
  EstimatorEpochResult processEpoch(const EstimatorEpochInput& input);
  /// Arcs that ended (slip, gap, end of data): their biases and held integers leave.
  void arcsEnded(const std::vector<EndedArc>& ended);
  /// The longest data gap whose arcs this estimator verifies and carries on
  /// (verifyBridgedArcs); nullopt (the default): a gap longer than the arc
  /// tracker's maximum ends the arcs.
  virtual std::optional<double> gapBridgeMax_s() const { return std::nullopt; }
  /// Whether the estimator uses the Doppler range rates (EstimatorEpochInput::doppler);
  /// the pipeline forms them only then. None by default.
  virtual bool usesDoppler() const { return false; }
  /// The last result of processEpoch(EstimatorEpochInput), with its ambiguity summary.
  const EstimatorEpochResult& lastResult() const { return last_; }
  /// The IMU state of an estimator with inertial states after the last epoch it
  /// reached; nullopt before its start and for a GNSS-only estimator (the default).
  virtual std::optional<InertialState> inertialState() const { return std::nullopt; }
  /// The antenna position this epoch's INS prediction gave (the readings since the
  /// last epoch, before the update), ECEF [m]: after a GNSS outage, the coasting
  /// position at its end. nullopt for a GNSS-only estimator (the default), before the
  /// start and at an epoch not predicted.
  virtual std::optional<Eigen::Vector3d> predictedAntennaPosition() const { return std::nullopt; }
  /// The smoothed trajectory of an estimator that smooths; nullptr for a filter.
  virtual const SmoothedTrajectoryProvider* smoothing() const { return nullptr; }
  /// The resolver (e.g. to hold an integer restored after a restart).
  AmbiguityResolver& resolver() { return ambiguity_; }

  /// Starting point of the code least squares of the first epoch (RINEX APPROX
  /// POSITION XYZ); the Earth centre otherwise.
  void setApproximatePosition(const Eigen::Vector3d& position_ecef_m) { approx_position_ecef_m_ = position_ecef_m; }
  const std::optional<Eigen::Vector3d>& approximatePosition() const { return approx_position_ecef_m_; }

  /// The measurement epoch, in time order (no arcs ended, no PPP-AR, not kept
  /// as lastResult()). `evaluate` linearises this epoch's
  /// measurements at a state; it is called during this call only.
  /// `evaluate_start` (nullable) is the start model, used only when the
  /// estimator starts without an approximate position (step 1); without it
  /// such a start is tried from the Earth centre with `evaluate` (which the
  /// full model refuses there: "no initial position").
  EstimatorEpochResult processEpoch(const GnssTime& time, const MeasurementFunction& evaluate,
                                    const MeasurementFunction* evaluate_start = nullptr);

  /// End an arc explicitly (e.g. the arc tracker reports it closed).
  void removeArc(ArcId arc);

  const ReceiverStateLayout& layout() const { return layout_; }
  /// Arcs with a bias state after the last epoch.
  virtual std::vector<ArcId> activeArcs() const = 0;
  /// Current estimate of an active arc's phase bias [m] (a smoother's: with all
  /// data so far); nullopt for an arc without a bias state.
  virtual std::optional<double> biasEstimate_m(ArcId arc) const = 0;
  const StochasticModel& stochasticModel() const { return model_; }
  /// Restarts after a failed update (from the last good state).
  int resets() const { return resets_; }

 protected:
  PppEstimator(StochasticModel model, ScreeningOptions screening, CodeLeastSquaresOptions start_options,
               ReceiverStateLayout layout, AmbiguityResolutionOptions ambiguity_resolution = {});

  /// PPP-AR on this epoch's float solution (the estimator's own step, called with
  /// phase biases only): fixes through resolver(), sets the result's summary.
  virtual void resolveAmbiguities(const EstimatorEpochInput& input, EstimatorEpochResult& result) = 0;
  /// The pipeline's input of the epoch, before the measurement epoch runs (e.g. the
  /// IMU readings of an estimator with inertial states); nothing by default.
  virtual void receiveEpochInput(const EstimatorEpochInput& /*input*/) {}
  /// The arcs back after a bridged gap, at the prediction (before the arc
  /// bookkeeping): each goes on or is ended (endBridgedArc). By default all end.
  virtual void verifyBridgedArcs(const std::vector<BridgedArc>& bridged, const std::vector<SatelliteMeasurement>& usable,
                                 EstimatorEpochResult& result);
  /// Ends a bridged arc: its bias and held integers leave; its measurements start a new bias.
  void endBridgedArc(const BridgedArc& bridged, const std::string& reason, EstimatorEpochResult& result);
  /// Applies another candidate of a bridged arc's slip repair (BridgedArcChanges); the
  /// epoch's measurements are then linearised again. False when the pipeline gave no
  /// way to or refused it.
  bool chooseRepairCandidate(const BridgedArc& bridged, const SlipCandidate& candidate, EstimatorEpochResult& result);

  /// A measurement that passed the prefit screening.
  struct ScreenedMeasurement {
    SatelliteMeasurement m;        // linearised at the prediction (clocks shifted)
    bool active_arc = false;       // its arc has a bias in the active set
    double new_arc_bias_m = 0.0;   // initial bias when not: phase minus code residual
  };
  struct EpochSolveInput {
    GnssTime time;
    double dt_s = 0.0;
    bool first = false;            // the estimator starts at this epoch
    ReceiverState predicted;       // clocks shifted
    std::vector<ArcId> dropped_arcs;  // leave the active set with this epoch's solution
    std::vector<ScreenedMeasurement> screened;
    const MeasurementFunction* evaluate = nullptr;
  };
  /// One measurement used by the solution.
  struct SolvedMeasurement {
    std::size_t screened_index = 0;
    SatelliteMeasurement m;        // at the estimator's last linearisation point
    bool new_arc = false;          // a new bias state was added
    double phase_prefit_m = 0.0;   // phase residual at the prediction minus the bias prior
    double code_postfit_m = 0.0;
    double phase_postfit_m = 0.0;
  };
  struct EpochSolveOutput {
    EpochSolution solution;
    std::vector<SolvedMeasurement> rows;
    AmbiguityState ambiguities = AmbiguityState::Float;
  };

  virtual bool hasState() const = 0;
  virtual std::optional<GnssTime> lastSolvedTime() const = 0;
  /// True when the estimator was initialised explicitly at exactly `time`.
  virtual bool startsAt(const GnssTime& /*time*/) const { return false; }
  /// The predicted receiver state over dt_s (first: no process noise); from
  /// `start` when the estimator has no state yet. May prepare a working copy.
  virtual ReceiverState predict(double dt_s, bool first, const std::optional<ReceiverState>& start) = 0;
  /// The predicted bias of an active arc (for the phase innovation test).
  virtual std::optional<ArcBiasPrior> predictedBias(ArcId arc) const = 0;
  /// The update; commits the estimator's state only when it returns true. On
  /// false it has set the result's status and reason (fail()).
  virtual bool solve(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result) = 0;
  /// After a Failed solve: restart from the last good state; true when it did.
  virtual bool recoverAfterFailure(EstimatorEpochResult& /*result*/) { return false; }
  virtual void arcRemoved(ArcId arc) = 0;
  virtual int biasCount() const = 0;
  /// Last touch of every epoch's result (solved or not), e.g. estimator diagnostics.
  virtual void finishEpoch(EstimatorEpochResult& /*result*/) const {}

  static bool fail(EstimatorEpochResult& result, EpochStatus status, NoSolutionReason why, std::string text);

  /// The ZWD's process variance over dt_s [m^2]: the random walk in time
  /// (StochasticModel::zwd) plus the height-driven term
  /// (StochasticModel::zwdHeightVariance_m2) for expectedHeightChange_m(dt_s).
  /// The EKF adds it in its prediction, the smoother in its between-state factor.
  double zwdProcessVariance_m2(double dt_s) const;
  /// The height change over dt_s [m] at the vertical rate of the solved (float)
  /// heights over the last kHeightRateWindow_s (the last two solutions when they are
  /// further apart), counting only the change beyond the heights' own noise
  /// (StochasticModel::zwdHeightChangeBeyondNoise_m with the sigma of their
  /// difference); 0 before the second solved epoch since the start.
  double expectedHeightChange_m(double dt_s) const;
  /// Keeps the solved height and its variance for expectedHeightChange_m (the
  /// history restarts with the estimator).
  void keepSolvedHeight(const GnssTime& time, const EpochSolution& solution, bool first);
  /// The span of solved heights whose difference gives the vertical rate [s]: long
  /// enough for a climb's change to stand out of the float's height noise, short
  /// enough to follow its start and end.
  static constexpr double kHeightRateWindow_s = 10.0;

  StochasticModel model_;
  ScreeningOptions screening_;
  /// The consistency test's quantiles for screening_.consistency_false_alarm (made
  /// when first needed and again when that probability changes; not estimator state).
  mutable std::optional<ChiSquareUpperQuantile> consistency_quantile_;
  CodeLeastSquaresOptions start_options_;
  ReceiverStateLayout layout_;

 private:
  struct ActiveArc {
    SatelliteId satellite;
    GnssTime last_used;
  };
  // The steps of processEpoch (numbered as in the comment at the top).
  EstimatorEpochResult finished(EstimatorEpochResult result, std::chrono::steady_clock::time_point t_start) const;
  bool startOrAdvance(const MeasurementFunction& evaluate, const MeasurementFunction* evaluate_start,
                      EpochSolveInput& in, std::optional<ReceiverState>& start, EstimatorEpochResult& result) const;
  std::vector<SatelliteMeasurement> lineariseAtPrediction(const MeasurementFunction& evaluate,
                                                          ReceiverState& predicted,
                                                          EstimatorEpochResult& result) const;
  std::map<ArcId, ActiveArc> bookArcs(const std::vector<SatelliteMeasurement>& usable, const GnssTime& time,
                                      std::vector<ArcId>& dropped_arcs) const;
  std::optional<std::vector<SatelliteMeasurement>> screenAgainstPriors(
      const std::vector<SatelliteMeasurement>& usable, const std::map<ArcId, ActiveArc>& arcs,
      EstimatorEpochResult& result) const;
  static std::vector<ScreenedMeasurement> withInitialBiases(std::vector<SatelliteMeasurement> kept,
                                                            const std::map<ArcId, ActiveArc>& arcs);
  bool solveOrRecover(const EpochSolveInput& in, EpochSolveOutput& out, EstimatorEpochResult& result);
  void commitEpoch(const EpochSolveInput& in, EpochSolveOutput out, std::map<ArcId, ActiveArc> arcs,
                   EstimatorEpochResult& result);
  void testConsistency(EstimatorEpochResult& result) const;

  std::optional<Eigen::Vector3d> approx_position_ecef_m_;
  std::map<ArcId, ActiveArc> arcs_;  // the active set
  std::vector<BridgedArc> bridged_;  // this epoch's arcs back after a bridged gap
  /// This epoch's EstimatorEpochInput::bridged_arc_changes (nullable).
  BridgedArcChanges* bridged_arc_changes_ = nullptr;
  /// The pipeline changed this epoch's arcs (a candidate chosen, an arc restarted): the
  /// measurements are linearised again.
  bool arcs_changed_ = false;
  int resets_ = 0;
  AmbiguityResolver ambiguity_;  // PPP-AR on the estimator's float solution
  /// A solved (float) height, for the vertical rate of expectedHeightChange_m.
  struct SolvedHeight {
    GnssTime time;
    double height_m = 0.0;       // ellipsoidal
    double variance_m2 = 0.0;    // of the height (the position covariance along the local up)
  };
  /// The solved heights of the last kHeightRateWindow_s since the start, at least the last two.
  std::deque<SolvedHeight> solved_heights_;
  EstimatorEpochResult last_;
};

}  // namespace ppp
