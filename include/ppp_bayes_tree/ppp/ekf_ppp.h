#pragma once
// EkfPpp: the reference extended Kalman filter for kinematic PPP.
//
// State: position (ECEF x, y, z) [m], zenith wet delay [m], receiver clock [m],
// then one ionosphere-free phase bias [m] per active arc (dynamic dimension).
// Per epoch:
//  1. predict over the real elapsed time dt (StochasticModel: random-walk
//     position/ZWD, white clock, constant biases);
//  2. linearise at the prediction through the caller's MeasurementFunction;
//     reject non-finite measurements; shift the white clock by the median code
//     residual (option); replace the bias of a satellite whose arc changed
//     (slip / new arc), drop biases of arcs unused for stale_arc_timeout_s;
//  3. prefit screening (EkfOptions), each rejection logged with its reason;
//  4. add a bias for each new arc: value (observed - predicted phase) -
//     (observed - predicted code), a priori sigma from the StochasticModel;
//  5. iterated measurement update with code and phase rows, Joseph form,
//     re-linearising through the MeasurementFunction; optional postfit check;
//  6. finite-value and positive-definiteness checks of x and P (P symmetrised).
// Too few satellites -> status NoSolution (no estimate, filter untouched: the
// next epoch predicts over the real elapsed time). A numerical failure -> status
// Failed with the reason, filter rolled back to its state before the epoch.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/code_least_squares.h"
#include "ppp_bayes_tree/ppp/ekf_options.h"
#include "ppp_bayes_tree/ppp/measurement_function.h"
#include "ppp_bayes_tree/ppp/stochastic_model.h"

namespace ppp {

enum class EpochStatus { Ok, NoSolution, Failed };
std::string toString(EpochStatus status);  // "ok", "no_solution", "failed"

using ReceiverCovariance = Eigen::Matrix<double, ReceiverState::kDim, ReceiverState::kDim>;

struct EpochSolution {
  ReceiverState state;
  ReceiverCovariance covariance = ReceiverCovariance::Zero();  // (x, y, z, zwd, clock) [m^2]
  Eigen::Matrix3d positionCovariance_m2() const { return covariance.topLeftCorner<3, 3>(); }
};

/// Residuals of one used satellite [m]. Prefit: at the prediction (after the
/// clock shift), phase minus the bias estimate (or its initial value for a new
/// arc). Postfit: at the updated state.
struct MeasurementResidual {
  SatelliteId satellite;
  ArcId arc = 0;
  bool new_arc = false;
  double elevation_rad = 0.0;
  double azimuth_rad = 0.0;
  double code_prefit_m = 0.0;
  double phase_prefit_m = 0.0;
  double code_postfit_m = 0.0;
  double phase_postfit_m = 0.0;
  double code_sigma_m = 0.0;
  double phase_sigma_m = 0.0;
};

struct EkfEpochResult {
  GnssTime time;
  EpochStatus status = EpochStatus::NoSolution;
  std::string reason;                     // empty when Ok
  std::optional<EpochSolution> solution;  // only when Ok
  double dt_s = 0.0;                      // elapsed since the last solved epoch (0 at the first)
  std::vector<SatelliteId> used;
  std::vector<RejectedSatellite> rejected;  // the model's rejections, then the estimator's
  int prefit_rejections = 0;
  int postfit_rejections = 0;
  int active_biases = 0;  // bias states after the epoch
  int iterations = 0;     // measurement-model evaluations
  std::vector<MeasurementResidual> residuals;  // same order as `used`
};

class EkfPpp {
 public:
  explicit EkfPpp(StochasticModel model = {}, EkfOptions options = {}, CodeLeastSquaresOptions start_options = {});

  /// Starting point of the code least squares that initialises the filter at
  /// its first epoch (RINEX APPROX POSITION XYZ); the Earth centre otherwise.
  void setApproximatePosition(const Eigen::Vector3d& position_ecef_m) { approx_position_ecef_m_ = position_ecef_m; }

  /// Initialise explicitly at `state` with the a priori sigmas (no biases).
  /// Otherwise processEpoch initialises from the code least squares.
  void initialise(const GnssTime& time, const ReceiverState& state);

  /// Process one epoch. `evaluate` linearises this epoch's measurements at a state.
  EkfEpochResult processEpoch(const GnssTime& time, const MeasurementFunction& evaluate);

  /// End an arc explicitly (e.g. the arc tracker reports it closed).
  void removeArc(ArcId arc);

  bool initialised() const { return initialised_; }
  std::optional<GnssTime> lastTime() const { return initialised_ ? std::optional<GnssTime>(last_time_) : std::nullopt; }
  ReceiverState receiverState() const;
  ReceiverCovariance receiverCovariance() const;
  int activeBiasCount() const { return static_cast<int>(f_.biases.size()); }
  std::vector<ArcId> activeArcs() const;
  std::optional<double> biasEstimate_m(ArcId arc) const;
  std::optional<double> biasSigma_m(ArcId arc) const;
  /// Full state and covariance (receiver part first, then biases in activeArcs() order).
  const Eigen::VectorXd& stateVector() const { return f_.x; }
  const Eigen::MatrixXd& covarianceMatrix() const { return f_.P; }

  /// The covariance the prediction over dt_s would give (filter unchanged).
  Eigen::MatrixXd predictedCovariance(double dt_s) const;

  const StochasticModel& stochasticModel() const { return model_; }
  const EkfOptions& options() const { return options_; }

 private:
  struct BiasSlot {
    ArcId arc = 0;
    SatelliteId satellite;
    GnssTime last_used;
  };
  struct Filter {  // everything an epoch may change (rolled back on failure)
    Eigen::VectorXd x;
    Eigen::MatrixXd P;
    std::vector<BiasSlot> biases;
  };
  struct Row;

  void predict(Filter& f, double dt_s, bool first) const;
  static void removeBias(Filter& f, std::size_t slot);
  static int findBias(const Filter& f, ArcId arc);

  StochasticModel model_;
  EkfOptions options_;
  CodeLeastSquaresOptions start_options_;
  std::optional<Eigen::Vector3d> approx_position_ecef_m_;
  bool initialised_ = false;
  bool fresh_ = false;  // initialised, no epoch processed yet
  GnssTime last_time_;
  Filter f_;
};

}  // namespace ppp
