#pragma once
// EstimatorEpochInput: what the pipeline gives an estimator (PppEstimator,
// ppp_estimator.h) for one epoch: the linearisation of its measurements, its
// usable observations with their arcs, the arcs that ended, the phase biases
// the IMU readings since the previous epoch and, for an estimator that uses
// them, the Doppler range rates.
#include <vector>

#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/ppp/model/doppler_observation.h"
#include "ppp_bayes_tree/ppp/model/measurement_function.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

class BiasProvider;

/// An arc back after a gap the arc tracker bridged (CycleSlipOptions::bridge_max_gap_s).
struct BridgedArc {
  SatelliteId satellite;
  ArcId arc = 0;
  double gap_s = 0.0;
  /// The geometry-free phase's jump over the gap [m] (SatelliteArcStatus::bridged_gf_jump_m).
  std::optional<double> gf_jump_m;
  double wavelength1_m = 0.0;  // of the first frequency
  /// f2^2 / (f1^2 - f2^2): the first frequency's phase is the ionosphere-free
  /// one minus this times the geometry-free one.
  double geometry_free_factor = 0.0;
  /// The slip repaired at this epoch (SatelliteArcStatus::slip_repair, accepted):
  /// the arc's phases are corrected by it; nullopt when its slip tests passed.
  std::optional<SlipRepair> repair;
};

/// The changes an estimator's gap bridge makes to the pipeline's arcs at this epoch
/// (the pipeline implements them, the arc tracker included). After either, `evaluate`
/// reads the arc's phases so changed.
class BridgedArcChanges {
 public:
  virtual ~BridgedArcChanges() = default;
  /// Applies another candidate of a bridged arc's slip repair (BridgedArc::repair, one
  /// of its alternatives): the arc's phases are corrected by it from this epoch on.
  /// False when it cannot be applied.
  virtual bool chooseRepairCandidate(const BridgedArc& bridged, const SlipCandidate& candidate) = 0;
  /// Starts a new arc for a bridged arc the estimator ended (PppEstimator::endBridgedArc):
  /// from this epoch on the satellite's phases belong to a new arc (a new id, the phases
  /// as observed), so no state of the ended arc is taken up again. Returns the new
  /// arc's id; nullopt when it cannot.
  virtual std::optional<ArcId> restartArc(const BridgedArc& bridged, const std::string& reason) = 0;
};

/// What the pipeline gives an estimator for one epoch.
struct EstimatorEpochInput {
  GnssTime time;
  /// Linearises this epoch's measurements at any receiver state (the single model).
  const MeasurementFunction* evaluate = nullptr;
  /// The start model (PppMeasurementModel::evaluateStart) for a start without an
  /// approximate position (PppEstimator::processEpoch); nullable.
  const MeasurementFunction* evaluate_start = nullptr;
  /// The usable dual-frequency observations and their arcs (same order).
  const std::vector<DualFrequencyObservation>* observations = nullptr;
  const std::vector<ArcId>* arcs = nullptr;
  /// Arcs that ended at this epoch (slip, gap) before this epoch's new arcs start.
  const std::vector<EndedArc>* ended_arcs = nullptr;
  /// Arcs that go on after a bridged gap, to be verified (PppEstimator::gapBridgeMax_s); nullable.
  const std::vector<BridgedArc>* bridged_arcs = nullptr;
  /// What the estimator's gap bridge may change in this epoch's arcs; nullable.
  BridgedArcChanges* bridged_arc_changes = nullptr;
  /// Satellite phase OSBs consistent with the clocks (phase_bias_consistency.h);
  /// nullptr when the products allow no integer ambiguities (float).
  const BiasProvider* phase_biases = nullptr;
  /// The IMU readings after the previous epoch up to this one (time order);
  /// nullptr without an IMU. Only an estimator with inertial states reads them.
  const std::vector<ImuSample>* imu = nullptr;
  /// The Doppler range rates of the selected satellites (doppler_observation.h);
  /// nullptr unless the estimator uses them (PppEstimator::usesDoppler).
  const std::vector<DopplerObservation>* doppler = nullptr;
};

}  // namespace ppp
