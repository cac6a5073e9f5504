#include "ppp_bayes_tree/ppp/model/arc_tracker.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

bool finiteObservation(const DualFrequencyObservation& o) {
  return std::isfinite(o.code1_m) && std::isfinite(o.code2_m) && std::isfinite(o.phase1_cycles) &&
         std::isfinite(o.phase2_cycles) && std::isfinite(o.frequency1_hz) && std::isfinite(o.frequency2_hz) &&
         o.frequency1_hz > 0.0 && o.frequency2_hz > 0.0 && o.frequency1_hz != o.frequency2_hz;
}

/// Arc starts a repair may undo: a slip test's or the receiver's loss of lock.
bool repairableStart(ArcStartReason reason) {
  return reason == ArcStartReason::MelbourneWuebbenaJump || reason == ArcStartReason::GeometryFreeJump ||
         reason == ArcStartReason::LossOfLock;
}

}  // namespace

double CycleSlipOptions::geometryFreeThreshold_m(double dt_s) const {
  return std::min(gf_threshold_base_m + gf_threshold_rate_mps * std::max(dt_s, 0.0), gf_threshold_max_m);
}

const char* arcStartReasonName(ArcStartReason reason) {
  switch (reason) {
    case ArcStartReason::None: return "none";
    case ArcStartReason::NewSatellite: return "new satellite";
    case ArcStartReason::LossOfLock: return "loss of lock";
    case ArcStartReason::DataGap: return "data gap";
    case ArcStartReason::MelbourneWuebbenaJump: return "Melbourne-Wubbena jump";
    case ArcStartReason::GeometryFreeJump: return "geometry-free jump";
  }
  return "unknown";
}

std::size_t ArcEpochResult::newArcCount() const {
  return static_cast<std::size_t>(
      std::count_if(satellites.begin(), satellites.end(), [](const auto& s) { return s.new_arc; }));
}

ArcTracker::ArcTracker(CycleSlipOptions options) : options_(std::move(options)) {}

double ArcTracker::interval_s() const { return interval_s_.value_or(options_.default_interval_s); }

double ArcTracker::maxGap_s() const {
  return options_.max_gap_s ? *options_.max_gap_s : options_.max_gap_intervals * interval_s();
}

double ArcTracker::arcKeepGap_s(double max_gap_s) const {
  return options_.bridge_max_gap_s ? std::max(max_gap_s, *options_.bridge_max_gap_s) : max_gap_s;
}

std::optional<ArcId> ArcTracker::currentArc(const SatelliteId& satellite) const {
  auto it = arcs_.find(satellite);
  if (it == arcs_.end() || !it->second.open) return std::nullopt;
  return it->second.id;
}

void ArcTracker::startArc(ArcState& state, const GnssTime& time, double mw, double gf) {
  state = ArcState{};
  state.id = next_id_++;
  state.open = true;
  state.first_time = time;
  state.last_time = time;
  state.epochs = 1;
  state.mw_mean = mw;
  state.mw_count = 1;
  state.gf_history.emplace_back(0.0, gf);
  recordRepairSample(state, 0.0, gf);
}

void ArcTracker::updateArc(ArcState& state, const GnssTime& time, double mw, double gf,
                           std::optional<double> gf_residual) const {
  if (gf_residual) {
    state.gf_res_count = std::min(state.gf_res_count + 1, std::max(options_.mw_window, 2));
    state.gf_res_ms += (*gf_residual * *gf_residual - state.gf_res_ms) / state.gf_res_count;
  }
  state.last_time = time;
  ++state.epochs;
  // Running mean / variance (Welford), forgetting exponentially beyond mw_window.
  state.mw_count = std::min(state.mw_count + 1, std::max(options_.mw_window, 2));
  const double n = state.mw_count;
  const double delta = mw - state.mw_mean;
  state.mw_mean += delta / n;
  state.mw_var += (delta * (mw - state.mw_mean) - state.mw_var) / n;
  state.gf_history.emplace_back(time - state.first_time, gf);
  recordRepairSample(state, time - state.first_time, gf);
  const auto keep = static_cast<std::size_t>(std::max(options_.gf_fit_points, 1));
  if (state.gf_history.size() > keep) state.gf_history.erase(state.gf_history.begin());
}

std::optional<double> ArcTracker::predictGeometryFree(const ArcState& state, const GnssTime& time) const {
  const auto& h = state.gf_history;
  if (h.empty()) return std::nullopt;
  const double t = time - state.first_time;
  if (h.size() == 1) return h.front().second;
  // Linear least squares gf = a + b (t - tm), extrapolated to t.
  double tm = 0.0, gm = 0.0;
  for (const auto& [ti, gi] : h) tm += ti, gm += gi;
  tm /= h.size();
  gm /= h.size();
  double stt = 0.0, stg = 0.0;
  for (const auto& [ti, gi] : h) stt += (ti - tm) * (ti - tm), stg += (ti - tm) * (gi - gm);
  const double slope = stt > 0.0 ? stg / stt : 0.0;
  return gm + slope * (t - tm);
}

double ArcTracker::geometryFreeThreshold_m(const ArcState& state, double dt_s) const {
  double thr = options_.geometryFreeThreshold_m(dt_s);
  if (state.gf_history.size() < 2) thr += options_.gf_drift_allowance_mps * std::max(dt_s, 0.0);
  if (state.gf_res_count >= options_.gf_min_samples)
    thr = std::max(thr, options_.gf_sigma_factor * std::sqrt(state.gf_res_ms));
  return thr;
}

EndedArc ArcTracker::endArc(const SatelliteId& sat, ArcState& state, std::string reason) const {
  state.open = false;
  return EndedArc{sat, state.id, state.first_time, state.last_time, state.epochs, std::move(reason)};
}

ArcEpochResult ArcTracker::process(const GnssTime& time,
                                   const std::vector<DualFrequencyObservation>& observations) {
  ArcEpochResult result;
  result.time = time;
  // 1. The epoch must follow the previous one; the shortest step is the interval.
  if (auto refusal = refuseEpoch(time)) {
    result.accepted = false;
    result.refusal_reason = std::move(*refusal);
    return result;
  }
  last_epoch_ = time;
  bridged_.clear();
  const double max_gap = maxGap_s();

  // 2. Each satellite once, with finite observations: its arc goes on or a new one starts.
  std::set<SatelliteId> seen;
  result.satellites.reserve(observations.size());
  for (const auto& obs : observations) {
    SatelliteArcStatus status;
    status.satellite = obs.satellite;
    if (!seen.insert(obs.satellite).second) {
      status.usable = false;
      status.reason = "satellite repeated in the epoch";
    } else if (!finiteObservation(obs)) {
      status.usable = false;
      status.reason = "non-finite observation or frequency";
    } else {
      trackSatellite(time, obs, max_gap, status, result);
    }
    result.satellites.push_back(std::move(status));
  }

  // 3. Arcs of satellites absent for longer than the maximum gap end now.
  for (auto& [sat, state] : arcs_) {
    if (!state.open || seen.count(sat) != 0) continue;
    const double absent = time - state.last_time;
    const double keep_gap = arcKeepGap_s(max_gap);
    if (absent > keep_gap)
      result.ended.push_back(endArc(sat, state, format("not observed for %.0f s > %.0f s", absent, keep_gap)));
  }
  return result;
}

std::optional<std::string> ArcTracker::refuseEpoch(const GnssTime& time) {
  if (!last_epoch_) return std::nullopt;
  const double dt = time - *last_epoch_;
  if (dt < 0.0) {
    return format("time goes backwards by %.3f s", -dt) + " (previous epoch " +
           last_epoch_->toString(TimeSystem::GPS, 1) + ")";
  }
  if (dt == 0.0) return "duplicate epoch " + time.toString(TimeSystem::GPS, 1);
  if (!interval_s_ || dt < *interval_s_) interval_s_ = dt;
  return std::nullopt;
}

void ArcTracker::trackSatellite(const GnssTime& time, const DualFrequencyObservation& obs, double max_gap,
                                SatelliteArcStatus& status, ArcEpochResult& result) {
  auto [it, inserted] = arcs_.try_emplace(obs.satellite);
  ArcState& state = it->second;
  correctedCombinations(obs, state.correction1_cycles, state.correction2_cycles, status);
  std::string text;
  std::optional<double> gf_residual;
  ArcStartReason reason = arcStart(state, inserted, obs, status, time, max_gap, text, gf_residual);
  const double gap_s = time - state.last_time;
  // A slip after a bridged gap: repaired when the identification is accepted.
  bool repaired = false;
  std::optional<ArcState> before_repair;
  if (repairableStart(reason) && gap_s > max_gap && repairActive()) {
    status.slip_repair = attemptRepair(state, obs, status, time);
    if (status.slip_repair->accepted()) {
      if (!status.slip_repair->alternatives.empty()) before_repair = state;
      gf_residual = applyRepair(state, obs, *status.slip_repair, status);
      reason = ArcStartReason::None;
      repaired = true;
    } else {
      text += "; not repaired: " + status.slip_repair->text;
    }
  }
  if (reason == ArcStartReason::None) {
    if (gap_s > max_gap) {
      status.bridged_gap_s = gap_s;
      status.bridged_gf_jump_m = gf_residual;
    }
    updateArc(state, time, status.mw_cycles, status.gf_m, repaired ? std::nullopt : gf_residual);
  } else {
    if (state.open) result.ended.push_back(endArc(obs.satellite, state, "replaced: " + text));
    if (state.correction1_cycles != 0 || state.correction2_cycles != 0) correctedCombinations(obs, 0, 0, status);
    startArc(state, time, status.mw_cycles, status.gf_m);
    status.new_arc = true;
    status.start_reason = reason;
    status.reason = std::move(text);
  }
  status.phase_correction1_cycles = state.correction1_cycles;
  status.phase_correction2_cycles = state.correction2_cycles;
  status.arc = state.id;
  if (status.bridged_gap_s > 0.0) bridged_[obs.satellite] = {obs, status, std::move(before_repair)};
}

std::optional<SatelliteArcStatus> ArcTracker::restartArc(const SatelliteId& satellite, const std::string& reason) {
  const auto bridged = bridged_.find(satellite);
  const auto it = arcs_.find(satellite);
  if (bridged == bridged_.end() || it == arcs_.end() || !it->second.open || !last_epoch_) return std::nullopt;
  ArcState& state = it->second;
  SatelliteArcStatus status;
  status.satellite = satellite;
  correctedCombinations(bridged->second.observation, 0, 0, status);
  endArc(satellite, state, reason);
  startArc(state, *last_epoch_, status.mw_cycles, status.gf_m);
  status.new_arc = true;
  status.start_reason = ArcStartReason::DataGap;
  status.reason = reason;
  status.arc = state.id;
  bridged_.erase(bridged);
  return status;
}

std::optional<SatelliteArcStatus> ArcTracker::chooseRepairCandidate(const SatelliteId& satellite,
                                                                    const SlipCandidate& candidate) {
  const auto it = bridged_.find(satellite);
  if (it == bridged_.end() || !it->second.before_repair || !it->second.status.slip_repair || !last_epoch_)
    return std::nullopt;
  BridgedAtLastEpoch& p = it->second;
  SlipRepair repair = *p.status.slip_repair;
  const bool known = std::any_of(repair.alternatives.begin(), repair.alternatives.end(),
                                 [&](const SlipCandidate& c) { return sameSlip(c, candidate); });
  if (!known) return std::nullopt;
  repair.choose(candidate);
  // That epoch again from the state before the repair, with the chosen slip.
  ArcState& state = arcs_[satellite];
  state = *p.before_repair;
  SatelliteArcStatus status = p.status;
  correctedCombinations(p.observation, state.correction1_cycles, state.correction2_cycles, status);
  const double gf_residual = applyRepair(state, p.observation, repair, status);
  status.bridged_gf_jump_m = gf_residual;
  updateArc(state, *last_epoch_, status.mw_cycles, status.gf_m, std::nullopt);
  status.slip_repair = repair;
  status.phase_correction1_cycles = state.correction1_cycles;
  status.phase_correction2_cycles = state.correction2_cycles;
  p.status = status;
  return status;
}

bool ArcTracker::repairActive() const { return options_.bridge_max_gap_s.has_value() && options_.slip_repair.enabled; }

void ArcTracker::correctedCombinations(const DualFrequencyObservation& obs, long correction1_cycles,
                                       long correction2_cycles, SatelliteArcStatus& status) {
  status.phase1_cycles = obs.phase1_cycles - static_cast<double>(correction1_cycles);
  status.phase2_cycles = obs.phase2_cycles - static_cast<double>(correction2_cycles);
  const double lambda1 = kSpeedOfLight_mps / obs.frequency1_hz;
  const double lambda2 = kSpeedOfLight_mps / obs.frequency2_hz;
  const double l1_m = status.phase1_cycles * lambda1;
  const double l2_m = status.phase2_cycles * lambda2;
  status.mw_cycles =
      melbourneWuebbena_cycles(l1_m, l2_m, obs.code1_m, obs.code2_m, obs.frequency1_hz, obs.frequency2_hz);
  status.gf_m = geometryFreePhase_m(l1_m, l2_m);
}

void ArcTracker::recordRepairSample(ArcState& state, double t_s, double gf_m) const {
  if (!repairActive()) return;
  auto& h = state.repair_gf_history;
  h.emplace_back(t_s, gf_m);
  const double window_s = options_.slip_repair.gf_fit_window_s;
  const auto first_kept = std::find_if(h.begin(), h.end(), [&](const auto& s) { return t_s - s.first <= window_s; });
  h.erase(h.begin(), first_kept);
}

SlipRepair ArcTracker::attemptRepair(const ArcState& state, const DualFrequencyObservation& obs,
                                     const SatelliteArcStatus& status, const GnssTime& time) const {
  SlipRepairInput in;
  in.mw_jump_cycles = status.mw_cycles - state.mw_mean;
  in.mw_sigma_cycles = state.mw_count >= options_.mw_min_samples ? std::sqrt(std::max(state.mw_var, 0.0))
                                                                  : options_.mw_initial_sigma_cycles;
  in.mw_samples = state.mw_count;
  in.gf_after_m = status.gf_m;
  in.gf_before = state.repair_gf_history;
  in.time_after_s = time - state.first_time;
  in.wavelength1_m = kSpeedOfLight_mps / obs.frequency1_hz;
  in.wavelength2_m = kSpeedOfLight_mps / obs.frequency2_hz;
  return repairSlip(in, options_.slip_repair);
}

double ArcTracker::applyRepair(ArcState& state, const DualFrequencyObservation& obs, const SlipRepair& repair,
                               SatelliteArcStatus& status) const {
  state.correction1_cycles += repair.dn1_cycles;
  state.correction2_cycles += repair.dn2_cycles;
  correctedCombinations(obs, state.correction1_cycles, state.correction2_cycles, status);
  return status.gf_m - repair.gf_prediction_m;
}

ArcStartReason ArcTracker::arcStart(const ArcState& state, bool inserted, const DualFrequencyObservation& obs,
                                    const SatelliteArcStatus& status, const GnssTime& time, double max_gap,
                                    std::string& text, std::optional<double>& gf_residual) const {
  if (inserted || state.id == 0) {
    text = "new satellite";
    return ArcStartReason::NewSatellite;
  }
  const double dt = time - state.last_time;
  if (dt > arcKeepGap_s(max_gap) || (dt > max_gap && !state.open)) {
    text = format("data gap %.0f s > %.0f s", dt, max_gap);
    return ArcStartReason::DataGap;
  }
  if (!state.open) {
    text = "new satellite";
    return ArcStartReason::NewSatellite;
  }
  if (options_.use_loss_of_lock && (obs.loss_of_lock1 || obs.loss_of_lock2)) {
    text = obs.loss_of_lock1 ? (obs.loss_of_lock2 ? "LLI set on L1 and L2" : "LLI set on L1") : "LLI set on L2";
    return ArcStartReason::LossOfLock;
  }
  return slipTest(state, status, time, dt, text, gf_residual);
}

ArcStartReason ArcTracker::slipTest(const ArcState& state, const SatelliteArcStatus& status, const GnssTime& time,
                                    double dt, std::string& text, std::optional<double>& gf_residual) const {
  const auto gf_pred = predictGeometryFree(state, time);
  const double gf_jump = gf_pred ? status.gf_m - *gf_pred : 0.0;
  const double gf_thr = geometryFreeThreshold_m(state, dt);
  if (state.gf_history.size() >= 2) gf_residual = gf_jump;
  const double sigma = state.mw_count >= options_.mw_min_samples ? std::sqrt(std::max(state.mw_var, 0.0))
                                                                  : options_.mw_initial_sigma_cycles;
  const double mw_thr = std::max(options_.mw_sigma_factor * sigma, options_.mw_min_threshold_cycles);
  const double mw_jump = status.mw_cycles - state.mw_mean;
  if (std::abs(mw_jump) > mw_thr) {
    text = format("Melbourne-Wubbena jump %.1f cycles > %.1f", std::abs(mw_jump), mw_thr);
    return ArcStartReason::MelbourneWuebbenaJump;
  }
  if (std::abs(gf_jump) > gf_thr) {
    text = format("geometry-free jump %.3f m > %.3f m", std::abs(gf_jump), gf_thr);
    return ArcStartReason::GeometryFreeJump;
  }
  return ArcStartReason::None;
}

std::vector<EndedArc> ArcTracker::finish() {
  std::vector<EndedArc> ended;
  for (auto& [sat, state] : arcs_)
    if (state.open) ended.push_back(endArc(sat, state, "end of data"));
  return ended;
}

}  // namespace ppp
