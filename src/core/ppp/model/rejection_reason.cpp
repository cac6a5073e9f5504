#include "ppp_bayes_tree/ppp/model/rejection_reason.h"

namespace ppp {

std::string toString(RejectionReason reason) {
  switch (reason) {
    case RejectionReason::SignalSelection: return "no usable signal pair";
    case RejectionReason::ArcTracking: return "refused by the arc tracker";
    case RejectionReason::LinearisationPointUnusable: return "linearisation point not usable";
    case RejectionReason::ObservationUnusable: return "observed IF code or phase not usable";
    case RejectionReason::NoClock: return "no clock";
    case RejectionReason::NoOrbit: return "no orbit";
    case RejectionReason::Eclipse: return "satellite in the Earth's shadow";
    case RejectionReason::YawManoeuvre: return "satellite in a yaw manoeuvre";
    case RejectionReason::MissingAntennaCalibration: return "missing antenna calibration";
    case RejectionReason::UndefinedPhaseCentreVariation: return "PCV undefined";
    case RejectionReason::BelowElevationCutoff: return "elevation below cutoff";
    case RejectionReason::UndefinedWindup: return "phase wind-up undefined";
    case RejectionReason::NoReceiverClock: return "no receiver clock for the system";
    case RejectionReason::NonFiniteModel: return "non-finite value";
    case RejectionReason::DuplicateMeasurement: return "duplicate measurement";
    case RejectionReason::CodeLeastSquaresOutlier: return "code least-squares residual";
    case RejectionReason::PrefitCode: return "prefit code residual";
    case RejectionReason::PrefitPhase: return "prefit phase-minus-code innovation";
    case RejectionReason::Relinearisation: return "left out at re-linearisation";
    case RejectionReason::PostfitCode: return "postfit code residual";
    case RejectionReason::PostfitPhase: return "postfit phase residual";
  }
  return "unknown";
}

std::string toString(NoSolutionReason reason) {
  switch (reason) {
    case NoSolutionReason::None: return "none";
    case NoSolutionReason::NoInitialPosition: return "no initial position";
    case NoSolutionReason::TooFewSatellites: return "too few satellites";
    case NoSolutionReason::EpochNotAfterLastSolved: return "epoch not after the last solved epoch";
    case NoSolutionReason::InnovationNotPositiveDefinite: return "innovation covariance not positive definite";
    case NoSolutionReason::NonFiniteState: return "non-finite state";
    case NoSolutionReason::CovarianceNotPositiveDefinite: return "covariance not positive definite";
    case NoSolutionReason::SmootherUpdateFailed: return "smoother update failed";
    case NoSolutionReason::NonFiniteFilteredEstimate: return "non-finite filtered estimate";
    case NoSolutionReason::InconsistentSolution: return "residuals inconsistent with the covariance";
    case NoSolutionReason::NoImuReadings: return "no IMU readings over the interval";
    case NoSolutionReason::NoInitialAttitude: return "no initial attitude";
  }
  return "unknown";
}

}  // namespace ppp
