#include "ppp_bayes_tree/ppp/ambiguity/wide_lane_ambiguity.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/model/time_correlated_noise.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

std::string toString(WideLaneBiasIssue issue) {
  switch (issue) {
    case WideLaneBiasIssue::None: return "none";
    case WideLaneBiasIssue::NoBiasProvider: return "no bias product";
    case WideLaneBiasIssue::MissingPhaseBias: return "no phase OSB for a selected phase";
    case WideLaneBiasIssue::MissingCodeBias: return "no code OSB for a selected code";
    case WideLaneBiasIssue::InvalidObservation: return "non-finite observation or frequencies";
  }
  return "unknown";
}

double melbourneWuebbena_cycles(const DualFrequencyObservation& o) {
  const double f1 = o.frequency1_hz, f2 = o.frequency2_hz;
  return melbourneWuebbena_cycles(o.phase1_cycles * kSpeedOfLight_mps / f1, o.phase2_cycles * kSpeedOfLight_mps / f2,
                                  o.code1_m, o.code2_m, f1, f2);
}

CorrectedMelbourneWuebbena correctedMelbourneWuebbena(const DualFrequencyObservation& obs,
                                                      const BiasProvider* biases) {
  CorrectedMelbourneWuebbena out;
  const double f1 = obs.frequency1_hz, f2 = obs.frequency2_hz;
  if (!(f1 > f2 && f2 > 0.0) || !std::isfinite(obs.phase1_cycles) || !std::isfinite(obs.phase2_cycles) ||
      !std::isfinite(obs.code1_m) || !std::isfinite(obs.code2_m)) {
    out.issue = WideLaneBiasIssue::InvalidObservation;
    return out;
  }
  if (!biases) {
    out.issue = WideLaneBiasIssue::NoBiasProvider;
    return out;
  }
  const BiasAnswer b1 = biases->phaseBias(obs.satellite, obs.phase1, obs.time);
  const BiasAnswer b2 = biases->phaseBias(obs.satellite, obs.phase2, obs.time);
  if (!b1.value_m || !b2.value_m) {
    out.issue = WideLaneBiasIssue::MissingPhaseBias;
    return out;
  }
  DualFrequencyObservation c = obs;
  c.phase1_cycles -= *b1.value_m * f1 / kSpeedOfLight_mps;
  c.phase2_cycles -= *b2.value_m * f2 / kSpeedOfLight_mps;
  if (!obs.code1_osb_m) {
    const BiasAnswer a = biases->codeBias(obs.satellite, obs.code1, obs.time);
    if (!a.value_m) {
      out.issue = WideLaneBiasIssue::MissingCodeBias;
      return out;
    }
    c.code1_m -= *a.value_m;
  }
  if (!obs.code2_osb_m) {
    const BiasAnswer a = biases->codeBias(obs.satellite, obs.code2, obs.time);
    if (!a.value_m) {
      out.issue = WideLaneBiasIssue::MissingCodeBias;
      return out;
    }
    c.code2_m -= *a.value_m;
  }
  out.mw_cycles = melbourneWuebbena_cycles(c);
  return out;
}

double roundingSuccessRate(double sigma_cycles) {
  if (!(sigma_cycles > 0.0)) return 1.0;
  return std::erf(1.0 / (2.0 * sigma_cycles * std::sqrt(2.0)));  // = 2 Phi(1/(2 sigma)) - 1
}

double WideLaneArcMean::sigmaOfMean_cycles(const WideLaneOptions& options) const {
  if (samples <= 0) return std::numeric_limits<double>::infinity();
  const double sample_sigma = samples > 1 ? std::sqrt(sum_squares / (samples - 1)) : 0.0;
  const double sigma = std::max(sample_sigma, options.min_sigma_cycles);
  const double independent =
      std::max(1.0, gaussMarkovEffectiveSamples(samples, meanInterval_s(), options.correlation_time_s));
  return sigma / std::sqrt(independent);
}

bool pairDetermined(const WideLaneArcMean& a, const WideLaneArcMean& b, const WideLaneOptions& options) {
  if (!a.restarted && !b.restarted) return true;
  if (a.samples < options.min_samples || b.samples < options.min_samples) return false;
  return roundingSuccessRate(std::hypot(a.sigmaOfMean_cycles(options), b.sigmaOfMean_cycles(options))) >=
         options.min_success_rate;
}

void WideLaneResolver::restartArc(ArcId arc) {
  const auto it = arcs_.find(arc);
  if (it == arcs_.end()) return;
  WideLaneArcMean restarted;
  restarted.arc = arc;
  restarted.satellite = it->second.satellite;
  restarted.restarted = true;
  it->second = restarted;
}

double WideLaneArcMean::meanInterval_s() const {
  if (samples < 2 || !first_time || !last_time) return 0.0;
  return (*last_time - *first_time) / (samples - 1);
}

int WideLaneResolution::fixedCount() const {
  int n = 0;
  for (const auto& a : arcs) n += a.fixed ? 1 : 0;
  return n;
}

WideLaneBiasIssue WideLaneResolver::add(ArcId arc, const DualFrequencyObservation& obs,
                                        const BiasProvider* biases) {
  const CorrectedMelbourneWuebbena mw = correctedMelbourneWuebbena(obs, biases);
  if (!mw.mw_cycles) return mw.issue;
  addValue(arc, obs.satellite, *mw.mw_cycles, obs.time);
  return WideLaneBiasIssue::None;
}

void WideLaneResolver::addValue(ArcId arc, const SatelliteId& satellite, double mw_cycles, const GnssTime& time) {
  if (!std::isfinite(mw_cycles)) return;
  WideLaneArcMean& m = arcs_[arc];
  m.arc = arc;
  m.satellite = satellite;
  if (!m.first_time) m.first_time = time;
  m.last_time = time;
  ++m.samples;
  const double delta = mw_cycles - m.mean_cycles;
  m.mean_cycles += delta / m.samples;
  m.sum_squares += delta * (mw_cycles - m.mean_cycles);
}

WideLaneResolution WideLaneResolver::resolve(const std::function<bool(ArcId)>& eligible) const {
  WideLaneResolution out;
  const WideLaneArcMean* ref = nullptr;
  for (const auto& [arc, m] : arcs_) {
    if (m.samples < options_.min_samples || (eligible && !eligible(arc))) continue;
    if (!ref) {
      ref = &m;
      continue;
    }
    const double s = m.sigmaOfMean_cycles(options_), sr = ref->sigmaOfMean_cycles(options_);
    if (s < sr || (s == sr && m.samples > ref->samples)) ref = &m;
  }
  if (!ref) return out;
  return resolveAgainst(ref->arc, eligible);
}

WideLaneResolution WideLaneResolver::resolveAgainst(ArcId reference_arc,
                                                    const std::function<bool(ArcId)>& eligible) const {
  WideLaneResolution out;
  const auto r = arcs_.find(reference_arc);
  if (r == arcs_.end() || r->second.samples < options_.min_samples) return out;
  const WideLaneArcMean* ref = &r->second;
  out.reference_arc = ref->arc;
  out.reference_satellite = ref->satellite;
  const double sigma_ref = ref->sigmaOfMean_cycles(options_);
  for (const auto& [arc, m] : arcs_) {
    if (m.samples < options_.min_samples || arc == ref->arc || (eligible && !eligible(arc))) continue;
    WideLaneFix f;
    f.arc = arc;
    f.satellite = m.satellite;
    f.float_cycles = m.mean_cycles - ref->mean_cycles;
    const double s = m.sigmaOfMean_cycles(options_);
    f.sigma_cycles = std::sqrt(s * s + sigma_ref * sigma_ref);
    f.success_rate = roundingSuccessRate(f.sigma_cycles);
    f.integer_cycles = std::lround(f.float_cycles);
    f.fraction_cycles = f.float_cycles - static_cast<double>(f.integer_cycles);
    f.fixed = f.success_rate >= options_.min_success_rate &&
              std::abs(f.fraction_cycles) <= options_.max_fraction_cycles;
    out.arcs.push_back(f);
  }
  return out;
}

}  // namespace ppp
