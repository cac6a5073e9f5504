#pragma once
// RejectionReason: why a satellite is left out of an epoch, as a value that
// counters, summaries and the ROS status use directly (never parsed back from
// text). The readable sentence with the numbers ("elevation 4.2 deg below cutoff
// 7.0 deg") travels beside it as the detail text.
#include <string>

namespace ppp {

enum class RejectionReason {
  SignalSelection,        // no usable dual-frequency pair (signal selection)
  ArcTracking,            // refused by the arc tracker (e.g. incomplete observation)
  LinearisationPointUnusable,  // the state the model is asked at is not a position
  ObservationUnusable,    // observed IF code / phase out of range
  NoClock,                // no satellite clock in the products at the epoch
  NoOrbit,                // no satellite orbit in the products at the epoch
  Eclipse,                // satellite in the Earth's shadow
  YawManoeuvre,           // satellite in a noon or midnight yaw turn (attitude not the nominal one)
  MissingAntennaCalibration,  // receiver or satellite antenna calibration missing
  UndefinedPhaseCentreVariation,  // PCV undefined at the zenith / nadir angle
  BelowElevationCutoff,
  UndefinedWindup,        // degenerate wind-up geometry
  NoReceiverClock,        // the satellite's system has no clock in the state layout
  NonFiniteModel,         // non-finite model value, measurement or sigma
  DuplicateMeasurement,   // a second measurement of the satellite in the epoch
  CodeLeastSquaresOutlier,
  PrefitCode,             // prefit code w-test
  PrefitPhase,            // prefit phase-minus-code innovation
  Relinearisation,        // left out or changed at re-linearisation (EKF iterations)
  PostfitCode,
  PostfitPhase,
};
/// Short readable name, e.g. "below elevation cutoff", "prefit code".
std::string toString(RejectionReason reason);

/// Why an epoch has no solution (EpochStatus NoSolution or Failed).
enum class NoSolutionReason {
  None,                     // solved
  NoInitialPosition,        // the code least squares of the first epoch failed
  TooFewSatellites,         // after screening
  EpochNotAfterLastSolved,  // time does not advance
  InnovationNotPositiveDefinite,
  NonFiniteState,
  CovarianceNotPositiveDefinite,
  SmootherUpdateFailed,     // the iSAM2 update threw (indeterminate system)
  NonFiniteFilteredEstimate,
  InconsistentSolution,     // postfit residuals fail the consistency test (withheld)
  NoImuReadings,            // an inertial estimator lacks IMU readings over the interval
  NoInitialAttitude,        // an inertial estimator was given no attitude to start from
};
std::string toString(NoSolutionReason reason);

}  // namespace ppp
