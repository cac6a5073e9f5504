#pragma once
// PppEpochProcessor: one observation epoch through the PPP chain, step by step
// (no ROS, no files): time checks -> signal selection -> arc tracking -> the
// measurement model -> a PppEstimator -> a PppEpochRecord.
// The offline PppPipeline (ppp_solve) streams a RINEX file through it, and the
// ROS nodes feed it epochs converted from messages with products from a
// CorrectionBuffer, so that both run exactly the same code per epoch.
//
// Time checks: an epoch at or before the last accepted one is refused (counted
// by the caller, never fatal); a spacing above 1.5 x the smallest spacing seen
// is reported as a gap. Epoch flag 6 (cycle-slip records) is refused.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/models/antenna_calibration_provider.h"
#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

class PppEpochProcessor {
 public:
  /// `ephemeris`, `biases` (nullable) and `ocean` (nullable) must outlive the
  /// processor; `antennas` may be null (no calibrations); `header` gives the
  /// observation types, receiver antenna and GLONASS channels (copied).
  PppEpochProcessor(const RinexObsHeader& header, const PppConfig& config, const EphemerisSource& ephemeris,
                    std::shared_ptr<const AntennaCalibrationProvider> antennas, const BiasProvider* biases,
                    const OceanLoadingCoefficients* ocean);
  ~PppEpochProcessor();
  PppEpochProcessor(const PppEpochProcessor&) = delete;
  PppEpochProcessor& operator=(const PppEpochProcessor&) = delete;

  /// Processes one epoch through `estimator` (time order). Refused epochs come
  /// back with `refused` set and the reason. `selection_notes` (nullable)
  /// receives the signal selection's code-reference notes of the epoch.
  PppEpochRecord process(const ObsEpoch& epoch, PppEstimator& estimator,
                         std::vector<SignalSelectionNote>* selection_notes = nullptr);
  /// Arcs still open at the end of the data (closes them in the tracker).
  std::vector<EndedArc> finish();
  /// Phase OSBs consistent with the clocks, handed to the estimators for
  /// ambiguity resolution (nullptr, the default: none, float).
  void setPhaseBiases(const BiasProvider* phase_biases);
  /// IMU readings in time order (nullable, must outlive the processor): each epoch
  /// hands the estimator those after the previous epoch up to its own time
  /// (EstimatorEpochInput::imu; the first epoch: all up to its time).
  void setImu(const std::vector<ImuSample>* readings);

  /// Replaces the observation types (the signal selector is rebuilt; arcs and
  /// wind-up continue). The receiver antenna is not changed.
  void setObservationTypes(const RinexObsHeader& header);
  const RinexObsHeader& header() const;
  /// Where each antenna calibration came from (see PppMeasurementModel).
  std::vector<std::string> antennaSources() const;
  /// L1-referenced orbits without a satellite calibration (see PppMeasurementModel).
  std::vector<std::string> satelliteReferenceNotes() const;
  /// What the receiver antenna policy "warn" left out (see PppMeasurementModel).
  const std::vector<std::string>& receiverAntennaWarnings() const;
  std::optional<GnssTime> lastTime() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ppp
