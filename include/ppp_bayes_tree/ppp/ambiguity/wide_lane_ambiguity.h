#pragma once
// Wide-lane ambiguities from Melbourne-Wuebbena (MW) means per arc, with the
// satellite wide-lane biases of observable-specific bias (OSB) products removed.
// Between-satellite single differences against a reference arc (the receiver
// bias cancels) are fixed by rounding when the rounding success probability
// reaches min_success_rate and the float lies within max_fraction_cycles of the
// integer. The sigma of an arc's mean counts the effective number of independent
// samples of a time-correlated error (time_correlated_noise.h), so the averaging
// length is a time. The formulas: doc/ppp_ar.md, "The wide lane".
// References: Melbourne W.G. (1985) and Wuebbena G. (1985), Proc. 1st Int. Symp.
// on Precise Positioning with GPS (the MW combination); Teunissen P.J.G. (1998)
// J Geod 72:606-612 (rounding success rate); Bartlett M.S. (1946) J R Stat Soc
// Suppl 8(1) (effective samples).
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"

namespace ppp {

/// Why an observation's MW could not be corrected for the satellite biases.
enum class WideLaneBiasIssue { None, NoBiasProvider, MissingPhaseBias, MissingCodeBias, InvalidObservation };
std::string toString(WideLaneBiasIssue issue);

struct CorrectedMelbourneWuebbena {
  std::optional<double> mw_cycles;  // set when issue == None
  WideLaneBiasIssue issue = WideLaneBiasIssue::None;
};

/// MW [wide-lane cycles] of one observation with the satellite OSBs removed.
CorrectedMelbourneWuebbena correctedMelbourneWuebbena(const DualFrequencyObservation& obs,
                                                      const BiasProvider* biases);

/// MW of the observation as observed (no bias removed) [wide-lane cycles]
/// (models/ionosphere_free.h's combination).
double melbourneWuebbena_cycles(const DualFrequencyObservation& obs);

struct WideLaneOptions {
  int min_samples = 10;              // epochs of an arc before it may be fixed
  double min_sigma_cycles = 0.15;    // floor of the per-epoch MW sigma [WL cycles]
  /// Correlation time of the MW errors [s] (0 = white). 15 s, the code
  /// multipath's (StochasticModel::code_correlation_time_s): 1.3 epochs per
  /// independent sample at 30 s, 30 at 1 Hz (the former fixed count of 4 epochs
  /// gave 1-Hz MW means a variance 7.5 times too small).
  double correlation_time_s = 15.0;
  double min_success_rate = 0.999;   // rounding success probability to fix
  double max_fraction_cycles = 0.25; // largest |float - integer| accepted
};

/// Running MW mean of one arc.
struct WideLaneArcMean {
  ArcId arc = 0;
  SatelliteId satellite;
  int samples = 0;
  double mean_cycles = 0.0;
  double sum_squares = 0.0;  // of deviations from the mean (Welford)
  std::optional<GnssTime> first_time, last_time;  // of the samples
  /// The mean started again at a slip repair (WideLaneResolver::restartArc): until it
  /// rounds (pairDetermined()), it cannot say whether the arc's wide lane changed.
  bool restarted = false;
  /// Mean interval between the samples [s] (0 with fewer than two).
  double meanInterval_s() const;
  /// Sigma of the mean [WL cycles] under the options' noise model.
  double sigmaOfMean_cycles(const WideLaneOptions& options) const;
};

/// Whether the single difference of two arcs' means can say their wide lane: always,
/// unless one of them was started again (WideLaneArcMean::restarted); then both need
/// min_samples and the difference a rounding success rate of min_success_rate.
bool pairDetermined(const WideLaneArcMean& a, const WideLaneArcMean& b, const WideLaneOptions& options);

/// One arc's single-differenced wide lane against the reference arc.
struct WideLaneFix {
  ArcId arc = 0;
  SatelliteId satellite;
  double float_cycles = 0.0;     // mean(arc) - mean(reference)
  double sigma_cycles = 0.0;
  double success_rate = 0.0;     // of rounding
  long integer_cycles = 0;       // nearest integer
  double fraction_cycles = 0.0;  // float - integer, in [-0.5, 0.5]
  bool fixed = false;
};

struct WideLaneResolution {
  std::optional<ArcId> reference_arc;  // nullopt: no arc had enough samples
  SatelliteId reference_satellite;
  std::vector<WideLaneFix> arcs;       // every eligible arc but the reference
  int fixedCount() const;
};

/// Accumulates MW per arc (fed by the caller with the arc ids of ArcTracker)
/// and resolves single-differenced wide lanes by rounding.
class WideLaneResolver {
 public:
  explicit WideLaneResolver(WideLaneOptions options = {}) : options_(options) {}

  /// Adds one corrected MW sample to `arc`; returns the issue when the
  /// observation could not be corrected (nothing added then).
  WideLaneBiasIssue add(ArcId arc, const DualFrequencyObservation& obs, const BiasProvider* biases);
  /// Adds an already corrected MW value [WL cycles] observed at `time`.
  void addValue(ArcId arc, const SatelliteId& satellite, double mw_cycles, const GnssTime& time);
  /// Forgets an arc (ended: slip, gap, satellite set).
  void removeArc(ArcId arc) { arcs_.erase(arc); }
  /// Starts the arc's mean again from the next sample (WideLaneArcMean::restarted): after
  /// a slip repair whose wide lane may be off by a slip common to its system (gap_bridge.h),
  /// the samples after it are in the arc's phases as repaired and those before may not be.
  void restartArc(ArcId arc);

  const std::map<ArcId, WideLaneArcMean>& arcs() const { return arcs_; }
  /// Single differences of the active arcs with at least min_samples samples
  /// (and, when given, accepted by `eligible`; the reference is one of them).
  WideLaneResolution resolve(const std::function<bool(ArcId)>& eligible = {}) const;
  /// The same against a given reference arc (no reference when that arc has
  /// fewer than min_samples samples).
  WideLaneResolution resolveAgainst(ArcId reference_arc, const std::function<bool(ArcId)>& eligible = {}) const;
  const WideLaneOptions& options() const { return options_; }

 private:
  WideLaneOptions options_;
  std::map<ArcId, WideLaneArcMean> arcs_;
};

/// Rounding success probability 2 Phi(1 / (2 sigma)) - 1 of a scalar.
double roundingSuccessRate(double sigma_cycles);

}  // namespace ppp
