#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"

#include <algorithm>

#include "ppp_bayes_tree/ppp/model/arc_tracker.h"

namespace ppp {

struct PppEpochProcessor::Impl {
  RinexObsHeader header;
  PppConfig config;
  const BiasProvider* biases = nullptr;
  const BiasProvider* phase_biases = nullptr;  // consistent with the clocks (PPP-AR)
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

  Impl(const RinexObsHeader& h, const PppConfig& c, const BiasProvider* b)
      : header(h), config(c), biases(b), tracker(c.cycle_slip_options) {}
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
  impl_->model = std::make_unique<PppMeasurementModel>(ephemeris, std::move(antennas),
                                                       ReceiverAntenna::fromHeader(header), ocean, config.model);
  impl_->selector = std::make_unique<SignalSelector>(impl_->header, config.signals, biases);
}

PppEpochProcessor::~PppEpochProcessor() = default;

void PppEpochProcessor::setPhaseBiases(const BiasProvider* phase_biases) { impl_->phase_biases = phase_biases; }

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

PppEpochRecord PppEpochProcessor::process(const ObsEpoch& epoch, PppEstimator& estimator,
                                          std::vector<SignalSelectionNote>* selection_notes) {
  Impl& d = *impl_;
  const std::vector<GnssSystem>& systems = d.config.signals.systems;
  const auto processed = [&](GnssSystem s) { return std::find(systems.begin(), systems.end(), s) != systems.end(); };
  PppEpochRecord rec;
  rec.solution.time = epoch.time;
  rec.solution.status = SolutionStatus::NoSolution;
  for (const auto& s : epoch.satellites)
    if (processed(s.satellite.system)) ++rec.satellites_observed;
  if (selection_notes) selection_notes->clear();

  const auto refuse = [&](const std::string& why) {
    rec.refused = true;
    rec.reason = why;
    return rec;
  };
  if (epoch.cycleSlipRecords()) return refuse("cycle-slip records (epoch flag 6), not observations");
  if (d.last_time && !(epoch.time > *d.last_time)) {
    return refuse(epoch.time == *d.last_time ? "duplicate epoch"
                                             : "time goes backwards by " + std::to_string(*d.last_time - epoch.time) +
                                                   " s");
  }
  if (d.last_time) {
    const double dt = epoch.time - *d.last_time;
    if (d.interval_s && dt > 1.5 * *d.interval_s) rec.gap_s = dt;
    d.interval_s = d.interval_s ? std::min(*d.interval_s, dt) : dt;
  }
  d.last_time = epoch.time;

  // Signal selection.
  d.selector->select(epoch, d.sel);
  rec.satellites_selected = static_cast<int>(d.sel.observations.size());
  for (const auto& s : d.sel.skipped) {
    if (!processed(s.satellite.system)) continue;
    rec.rejected.push_back({s.satellite, RejectionStage::Signals, RejectionReason::SignalSelection, s.reason});
  }
  if (selection_notes) *selection_notes = d.sel.notes;

  // Arc tracking: ids, slips, ended arcs.
  const ArcEpochResult arc_result = d.tracker.process(epoch.time, d.sel.observations);
  if (!arc_result.accepted) return refuse(arc_result.refusal_reason);  // guard: the time check comes first
  d.usable.clear();
  d.arcs.clear();
  for (std::size_t i = 0; i < arc_result.satellites.size(); ++i) {
    const auto& st = arc_result.satellites[i];
    if (!st.usable) {
      rec.rejected.push_back({st.satellite, RejectionStage::Arcs, RejectionReason::ArcTracking, st.reason});
      continue;
    }
    if (st.new_arc) {
      ++rec.new_arcs;
      if (st.start_reason == ArcStartReason::MelbourneWuebbenaJump ||
          st.start_reason == ArcStartReason::GeometryFreeJump || st.start_reason == ArcStartReason::LossOfLock)
        ++rec.slips;
      if (st.start_reason != ArcStartReason::NewSatellite)
        rec.arc_events.push_back(st.satellite.toString() + " arc " + std::to_string(st.arc) + ": " + st.reason);
    }
    d.usable.push_back(d.sel.observations[i]);
    d.arcs.push_back(st.arc);
  }

  // The single measurement model, linearised at whatever state the estimator asks.
  const MeasurementFunction evaluate = [&](const ReceiverState& state) {
    EpochMeasurements m;
    d.model->evaluate(d.usable, d.arcs, state, &d.windup, m);
    m.time = epoch.time;
    return m;
  };
  // The start model, for an estimator that starts without an approximate position.
  const MeasurementFunction evaluate_start = [&](const ReceiverState& state) {
    EpochMeasurements m;
    d.model->evaluateStart(d.usable, state, m);
    m.time = epoch.time;
    return m;
  };
  EstimatorEpochInput input;
  input.time = epoch.time;
  input.evaluate = &evaluate;
  input.evaluate_start = &evaluate_start;
  input.observations = &d.usable;
  input.arcs = &d.arcs;
  input.ended_arcs = &arc_result.ended;
  input.phase_biases = impl_->phase_biases;
  EstimatorEpochResult r = estimator.processEpoch(input);

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
    recordFixRatio(impl_->fix_ratio, s, r);
    s.position_ecef_m = r.solution->state.position_ecef_m;
    s.covariance_ecef_m2 = r.solution->positionCovariance_m2();
    s.zwd_m = r.solution->state.zwd_m;
    s.receiver_clock_m = r.solution->state.referenceClock_m();
    rec.state_layout = r.solution->state.layout;
    rec.receiver_covariance = r.solution->covariance;
  }
  if (s.status != SolutionStatus::PppFixed) impl_->fix_ratio.reset();
  rec.active_biases = r.active_biases;
  rec.estimator_reset = r.estimator_reset;
  rec.estimator_time_s = r.epoch_time_s;
  rec.smoother = std::move(r.smoother);
  rec.ambiguity_fix = std::move(r.ambiguity_fix);
  return rec;
}

}  // namespace ppp
