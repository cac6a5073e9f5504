#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"

#include <algorithm>

#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/ppp/model/observed_ionosphere_free.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

struct PppEpochProcessor::Impl : BridgedArcChanges {
  RinexObsHeader header;
  PppConfig config;
  const BiasProvider* biases = nullptr;
  const BiasProvider* phase_biases = nullptr;  // consistent with the clocks (PPP-AR)
  const std::vector<ImuSample>* imu = nullptr;  // IMU readings (time order), nullable
  std::size_t imu_next = 0;                     // the first reading not yet handed on
  std::vector<ImuSample> imu_epoch;             // the readings of this epoch
  std::unique_ptr<PppMeasurementModel> model;
  std::unique_ptr<SignalSelector> selector;
  ArcTracker tracker;
  WindupTracker windup;
  std::optional<GnssTime> last_time;
  std::optional<double> interval_s;
  /// The ratio of the latest integer search that passed while the solution stays
  /// fixed (held integers need no search every epoch): SolutionEpoch::ambiguity_ratio.
  std::optional<double> fix_ratio;
  // Work buffers reused every epoch.
  SignalSelectionResult sel;
  std::vector<DualFrequencyObservation> usable;
  std::vector<ArcId> arcs;
  std::vector<ObservedIonosphereFree> observed_if;  // of `usable`, once per epoch for every linearisation
  std::vector<BridgedArc> bridged;
  /// The slip-repair candidates the estimator chose at this epoch (chooseRepairCandidate).
  std::vector<ArcSlipRepair> chosen_repairs;
  const EphemerisSource* ephemeris = nullptr;
  DopplerEpoch doppler;  // this epoch's Doppler range rates (an estimator that uses them)

  Impl(const RinexObsHeader& h, const PppConfig& c, const BiasProvider* b)
      : header(h), config(c), biases(b), tracker(c.cycle_slip_options) {}

  /// Notes a data gap before the epoch and moves the last time on.
  void advanceTime(const ObsEpoch& epoch, PppEpochRecord& rec);
  /// Each satellite's dual-frequency signals; the skipped ones as rejections.
  void selectSignals(const ObsEpoch& epoch, PppEpochRecord& rec, std::vector<SignalSelectionNote>* selection_notes);
  /// The usable satellites (the arcs' phases), their arcs and observed IF; new arcs and slips counted.
  void keepUsableArcs(const ArcEpochResult& arc_result, PppEpochRecord& rec);
  /// The IMU readings after the previous epoch up to `time` (nullptr without an IMU).
  const std::vector<ImuSample>* imuUpTo(const GnssTime& time);
  /// The estimator's step over the single measurement model of the usable satellites.
  EstimatorEpochResult estimate(const ObsEpoch& epoch, const ArcEpochResult& arc_result, PppEstimator& estimator);
  /// Another candidate of a bridged arc's repair applied: the tracker's arc, the usable
  /// phases, the observed IF.
  bool chooseRepairCandidate(const BridgedArc& bridged_arc, const SlipCandidate& candidate) override;
  /// A bridged arc the estimator ended starts again as a new arc: the tracker's arc, the
  /// usable phases and arc, the observed IF.
  std::optional<ArcId> restartArc(const BridgedArc& bridged_arc, const std::string& reason) override;
  /// The usable satellite `arc` is at (its index in `usable` and `arcs`) takes the
  /// tracker's new status: its phases, its arc, the observed IF.
  void takeArcStatus(std::size_t i, const SatelliteArcStatus& status);
  /// The arcs restarted at this epoch: (old, new status).
  std::vector<std::pair<ArcId, SatelliteArcStatus>> restarted;
};

namespace {

/// A fixed epoch's ratio: this epoch's search when it passed, else the latest that
/// passed since the solution became fixed (the held integers'); nullopt when none.
void recordFixRatio(std::optional<double>& fix_ratio, SolutionEpoch& s, const EstimatorEpochResult& r) {
  if (s.status != SolutionStatus::PppFixed || !r.ambiguity_fix) return;
  const AmbiguityFixSummary& f = *r.ambiguity_fix;
  if (f.ils_reason == IlsFloatReason::None && f.ratio > 0.0) fix_ratio = f.ratio;
  s.ambiguity_ratio = fix_ratio;
}

}  // namespace

PppEpochProcessor::PppEpochProcessor(const RinexObsHeader& header, const PppConfig& config,
                                     const EphemerisSource& ephemeris,
                                     std::shared_ptr<const AntennaCalibrationProvider> antennas,
                                     const BiasProvider* biases, const OceanLoadingCoefficients* ocean)
    : impl_(std::make_unique<Impl>(header, config, biases)) {
  impl_->ephemeris = &ephemeris;
  impl_->model = std::make_unique<PppMeasurementModel>(ephemeris, std::move(antennas),
                                                       ReceiverAntenna::fromHeader(header), ocean, config.model);
  impl_->selector = std::make_unique<SignalSelector>(impl_->header, config.signals, biases);
}

PppEpochProcessor::~PppEpochProcessor() = default;

void PppEpochProcessor::setPhaseBiases(const BiasProvider* phase_biases) { impl_->phase_biases = phase_biases; }

void PppEpochProcessor::setImu(const std::vector<ImuSample>* readings) {
  impl_->imu = readings;
  impl_->imu_next = 0;
}

const std::vector<ImuSample>* PppEpochProcessor::Impl::imuUpTo(const GnssTime& time) {
  if (!imu) return nullptr;
  imu_epoch.clear();
  while (imu_next < imu->size() && (*imu)[imu_next].time - time <= 0.0) imu_epoch.push_back((*imu)[imu_next++]);
  return &imu_epoch;
}

void PppEpochProcessor::setObservationTypes(const RinexObsHeader& header) {
  impl_->header.obs_types = header.obs_types;
  impl_->header.scale_factors = header.scale_factors;
  impl_->header.glonass_channels = header.glonass_channels;
  impl_->header.phase_shifts = header.phase_shifts;
  impl_->selector = std::make_unique<SignalSelector>(impl_->header, impl_->config.signals, impl_->biases);
}

const RinexObsHeader& PppEpochProcessor::header() const { return impl_->header; }

std::vector<std::string> PppEpochProcessor::antennaSources() const { return impl_->model->antennaSources(); }

std::vector<std::string> PppEpochProcessor::satelliteReferenceNotes() const {
  return impl_->model->satelliteReferenceNotes();
}

const std::vector<std::string>& PppEpochProcessor::receiverAntennaWarnings() const {
  return impl_->model->receiverAntennaWarnings();
}

std::optional<GnssTime> PppEpochProcessor::lastTime() const { return impl_->last_time; }

std::vector<EndedArc> PppEpochProcessor::finish() { return impl_->tracker.finish(); }

namespace {

/// Whether the configuration processes `system`.
bool processedSystem(const PppConfig& config, GnssSystem system) {
  const std::vector<GnssSystem>& systems = config.signals.systems;
  return std::find(systems.begin(), systems.end(), system) != systems.end();
}

/// Refuses the epoch: not processed at all, with the reason.
PppEpochRecord& refuseEpoch(PppEpochRecord& rec, const std::string& why) {
  rec.refused = true;
  rec.reason = why;
  return rec;
}

/// Why an epoch cannot be processed at all (special records, time not moving
/// forward); empty when it can.
std::string timeRefusal(const ObsEpoch& epoch, const std::optional<GnssTime>& last_time) {
  if (epoch.cycleSlipRecords()) return "cycle-slip records (epoch flag 6), not observations";
  if (!last_time || epoch.time > *last_time) return {};
  if (epoch.time == *last_time) return "duplicate epoch";
  return "time goes backwards by " + std::to_string(*last_time - epoch.time) + " s";
}

/// Whether an arc start is a slip (a detected jump or a loss of lock).
bool startedBySlip(ArcStartReason reason) {
  return reason == ArcStartReason::MelbourneWuebbenaJump || reason == ArcStartReason::GeometryFreeJump ||
         reason == ArcStartReason::LossOfLock;
}

/// The estimator's epoch result in the record and its solution.
void recordEstimate(EstimatorEpochResult& r, std::optional<double>& fix_ratio, PppEpochRecord& rec) {
  rec.status = r.status;
  rec.no_solution_reason = r.no_solution_reason;
  rec.reason = r.reason;
  rec.consistency = r.consistency;
  rec.used = r.used;
  for (const auto& x : r.rejected) rec.rejected.push_back({x.satellite, RejectionStage::Model, x.reason, x.detail});
  rec.residuals = std::move(r.residuals);
  SolutionEpoch& s = rec.solution;
  s.satellites_used = static_cast<int>(rec.used.size());
  s.satellites_rejected = static_cast<int>(rec.rejected.size());
  s.integrity = r.integrity;
  if (r.status == EpochStatus::Ok && r.solution) {
    s.status = r.ambiguities == AmbiguityState::Fixed ? SolutionStatus::PppFixed : SolutionStatus::PppFloat;
    recordFixRatio(fix_ratio, s, r);
    s.position_ecef_m = r.solution->state.position_ecef_m;
    s.covariance_ecef_m2 = r.solution->positionCovariance_m2();
    s.zwd_m = r.solution->state.zwd_m;
    s.receiver_clock_m = r.solution->state.referenceClock_m();
    rec.state_layout = r.solution->state.layout;
    rec.receiver_covariance = r.solution->covariance;
  }
  if (s.status != SolutionStatus::PppFixed) fix_ratio.reset();
  rec.active_biases = r.active_biases;
  rec.estimator_reset = r.estimator_reset;
  rec.estimator_time_s = r.epoch_time_s;
  rec.smoother = std::move(r.smoother);
  rec.ambiguity_fix = std::move(r.ambiguity_fix);
}

}  // namespace

void PppEpochProcessor::Impl::advanceTime(const ObsEpoch& epoch, PppEpochRecord& rec) {
  if (last_time) {
    const double dt = epoch.time - *last_time;
    if (interval_s && dt > 1.5 * *interval_s) rec.gap_s = dt;
    interval_s = interval_s ? std::min(*interval_s, dt) : dt;
  }
  last_time = epoch.time;
}

void PppEpochProcessor::Impl::selectSignals(const ObsEpoch& epoch, PppEpochRecord& rec,
                                            std::vector<SignalSelectionNote>* selection_notes) {
  selector->select(epoch, sel);
  rec.satellites_selected = static_cast<int>(sel.observations.size());
  for (const auto& s : sel.skipped) {
    if (!processedSystem(config, s.satellite.system)) continue;
    rec.rejected.push_back({s.satellite, RejectionStage::Signals, RejectionReason::SignalSelection, s.reason});
  }
  if (selection_notes) *selection_notes = sel.notes;
}

void PppEpochProcessor::Impl::keepUsableArcs(const ArcEpochResult& arc_result, PppEpochRecord& rec) {
  usable.clear();
  arcs.clear();
  bridged.clear();
  for (std::size_t i = 0; i < arc_result.satellites.size(); ++i) {
    const auto& st = arc_result.satellites[i];
    if (!st.usable) {
      rec.rejected.push_back({st.satellite, RejectionStage::Arcs, RejectionReason::ArcTracking, st.reason});
      continue;
    }
    if (st.new_arc) {
      ++rec.new_arcs;
      if (startedBySlip(st.start_reason)) ++rec.slips;
      if (st.start_reason != ArcStartReason::NewSatellite)
        rec.arc_events.push_back(st.satellite.toString() + " arc " + std::to_string(st.arc) + ": " + st.reason);
    }
    const bool repaired = st.slip_repair && st.slip_repair->accepted();
    if (st.slip_repair && !repaired) ++rec.slip_repairs_refused;
    if (repaired) rec.slip_repairs.push_back({st.satellite, st.arc, *st.slip_repair});
    if (st.bridged_gap_s > 0.0) {
      const DualFrequencyObservation& o = sel.observations[i];
      const double f1 = o.frequency1_hz, f2 = o.frequency2_hz;
      bridged.push_back({st.satellite, st.arc, st.bridged_gap_s, st.bridged_gf_jump_m, kSpeedOfLight_mps / f1,
                         f2 * f2 / (f1 * f1 - f2 * f2), repaired ? st.slip_repair : std::nullopt});
    }
    usable.push_back(sel.observations[i]);
    // The arc's phases: its repaired slips taken off by the tracker.
    usable.back().phase1_cycles = st.phase1_cycles;
    usable.back().phase2_cycles = st.phase2_cycles;
    arcs.push_back(st.arc);
  }
  observedIonosphereFree(usable, observed_if);
}

void PppEpochProcessor::Impl::takeArcStatus(std::size_t i, const SatelliteArcStatus& status) {
  usable[i].phase1_cycles = status.phase1_cycles;
  usable[i].phase2_cycles = status.phase2_cycles;
  arcs[i] = status.arc;
  observedIonosphereFree(usable, observed_if);
}

bool PppEpochProcessor::Impl::chooseRepairCandidate(const BridgedArc& bridged_arc, const SlipCandidate& candidate) {
  const auto it = std::find(arcs.begin(), arcs.end(), bridged_arc.arc);
  if (it == arcs.end()) return false;
  const std::optional<SatelliteArcStatus> st = tracker.chooseRepairCandidate(bridged_arc.satellite, candidate);
  if (!st || st->arc != bridged_arc.arc || !st->slip_repair) return false;
  takeArcStatus(static_cast<std::size_t>(it - arcs.begin()), *st);
  chosen_repairs.push_back({st->satellite, st->arc, *st->slip_repair});
  return true;
}

std::optional<ArcId> PppEpochProcessor::Impl::restartArc(const BridgedArc& bridged_arc, const std::string& reason) {
  const auto it = std::find(arcs.begin(), arcs.end(), bridged_arc.arc);
  if (it == arcs.end()) return std::nullopt;
  std::optional<SatelliteArcStatus> st = tracker.restartArc(bridged_arc.satellite, "ended by the gap bridge: " + reason);
  if (!st) return std::nullopt;
  takeArcStatus(static_cast<std::size_t>(it - arcs.begin()), *st);
  restarted.emplace_back(bridged_arc.arc, std::move(*st));
  return restarted.back().second.arc;
}

EstimatorEpochResult PppEpochProcessor::Impl::estimate(const ObsEpoch& epoch, const ArcEpochResult& arc_result,
                                                       PppEstimator& estimator) {
  const GnssTime& time = epoch.time;
  // The single measurement model, linearised at whatever state the estimator asks.
  const MeasurementFunction evaluate = [&](const ReceiverState& state) {
    EpochMeasurements m;
    model->evaluate(usable, observed_if, arcs, state, &windup, m);
    m.time = time;
    return m;
  };
  // The start model, for an estimator that starts without an approximate position.
  const MeasurementFunction evaluate_start = [&](const ReceiverState& state) {
    EpochMeasurements m;
    model->evaluateStart(usable, observed_if, state, m);
    m.time = time;
    return m;
  };
  EstimatorEpochInput input;
  input.time = time;
  input.evaluate = &evaluate;
  input.evaluate_start = &evaluate_start;
  input.observations = &usable;
  input.arcs = &arcs;
  input.ended_arcs = &arc_result.ended;
  input.bridged_arcs = &bridged;
  chosen_repairs.clear();
  restarted.clear();
  input.bridged_arc_changes = this;
  input.phase_biases = phase_biases;
  input.imu = imuUpTo(time);
  if (estimator.usesDoppler()) {  // every satellite's Doppler of the processed systems, arcs or not
    doppler = dopplerObservations(epoch, sel.observations, config.signals.systems, header.glonass_channels,
                                  *ephemeris);
    input.doppler = &doppler.observations;
  }
  return estimator.processEpoch(input);
}

// One epoch, as numbered steps:
//   1. refuse special records and time that does not move forward; note a gap;
//   2. select each satellite's dual-frequency signals;
//   3. track arcs (ids, slips, ended arcs) and keep the usable satellites;
//   4. the estimator's step over the single measurement model;
//   5. the estimator's result into the record.
PppEpochRecord PppEpochProcessor::process(const ObsEpoch& epoch, PppEstimator& estimator,
                                          std::vector<SignalSelectionNote>* selection_notes) {
  Impl& d = *impl_;
  PppEpochRecord rec;
  rec.solution.time = epoch.time;
  rec.solution.status = SolutionStatus::NoSolution;
  for (const auto& s : epoch.satellites)
    if (processedSystem(d.config, s.satellite.system)) ++rec.satellites_observed;
  if (selection_notes) selection_notes->clear();

  // 1. Special records and time that does not move forward are refused.
  if (const std::string why = timeRefusal(epoch, d.last_time); !why.empty()) return refuseEpoch(rec, why);
  d.advanceTime(epoch, rec);
  // 2. Signal selection.
  d.selectSignals(epoch, rec, selection_notes);
  // 3. Arc tracking (the time check above comes first, so a refusal here is a guard).
  d.tracker.setBridgeMaxGap_s(estimator.gapBridgeMax_s());
  const ArcEpochResult arc_result = d.tracker.process(epoch.time, d.sel.observations);
  if (!arc_result.accepted) return refuseEpoch(rec, arc_result.refusal_reason);
  d.keepUsableArcs(arc_result, rec);
  // 4. The estimator's step.
  EstimatorEpochResult r = d.estimate(epoch, arc_result, estimator);
  // The repairs as the estimator chose them among their candidates.
  for (const ArcSlipRepair& chosen : d.chosen_repairs)
    for (ArcSlipRepair& repair : rec.slip_repairs)
      if (repair.arc == chosen.arc) repair.repair = chosen.repair;
  // Arcs the estimator ended after a bridged gap start again as new arcs.
  for (const auto& [old_arc, st] : d.restarted) {
    ++rec.new_arcs;
    rec.arc_events.push_back(st.satellite.toString() + " arc " + std::to_string(st.arc) + " (was arc " +
                             std::to_string(old_arc) + "): " + st.reason);
  }
  // 5. Its result into the record.
  recordEstimate(r, d.fix_ratio, rec);
  return rec;
}

}  // namespace ppp
