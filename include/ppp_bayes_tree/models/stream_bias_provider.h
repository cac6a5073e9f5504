#pragma once
// StreamBiasProvider: satellite code and phase biases for integer ambiguity
// resolution that arrive as a stream of batches (one batch per product epoch,
// the PreciseCorrections message's satellites[].biases; the form an SSR phase
// bias feed such as RTCM 1265-1270 or IGS-SSR publishes: one observable-specific
// bias per satellite and signal, in metres, corrected = observed - bias).
//
// The answer at t is the value of the newest batch at or before t that carries
// the satellite and signal (a bias holds until the next batch replaces it, as SSR
// phase biases do between updates); nothing before the first batch. Batches older
// than `history_s` before the newest are dropped with their values, so the memory
// stays bounded and a satellite the stream stops sending goes absent (an infinite
// `history_s` keeps every batch, as ppp_bag_solve does for a whole bag).
// Each answer holds for the asked instant only (a later batch may change it).
#include <map>
#include <optional>
#include <string>
#include <set>
#include <utility>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/models/bias_provider.h"

namespace ppp {

/// One observable-specific bias: `code` is a RINEX 3 code ("C1W" code, "L1W" phase).
struct ObservableBias {
  ObservationCode code;
  double bias_m = 0.0;
};

/// The biases of one product epoch.
struct SatelliteBiasBatch {
  GnssTime time;  // GPST
  std::string source;  // what the biases are, e.g. "GRG0MGXFIN..CLK (wide-lane biases of integer-recovery clocks)"
  std::map<SatelliteId, std::vector<ObservableBias>> biases;
};

/// The biases `provider` gives at `t` for `satellites` and the code and phase
/// observation types of their systems in `header` (a batch for a stream).
SatelliteBiasBatch sampleBiases(const BiasProvider& provider, const GnssTime& t, const RinexObsHeader& header,
                                const std::vector<SatelliteId>& satellites);

class StreamBiasProvider : public BiasProvider {
 public:
  explicit StreamBiasProvider(double history_s = 900.0) : history_s_(history_s) {}
  /// Adds a batch (a batch without biases is ignored; one at an epoch already held replaces it).
  void add(const SatelliteBiasBatch& batch);
  void clear();
  bool empty() const { return series_.empty(); }
  /// The source text of the newest batch ("" before any).
  const std::string& source() const { return source_; }
  std::size_t batches() const { return batch_times_.size(); }

  BiasAnswer codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  BiasAnswer phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  std::string describeSource() const override;

 private:
  using Key = std::pair<SatelliteId, ObservationCode>;
  BiasAnswer lookup(const Key& key, const GnssTime& t) const;
  void prune();
  double history_s_;
  std::map<Key, std::map<GnssTime, double>> series_;  // per satellite and observable: value by batch time
  std::set<GnssTime> batch_times_;
  std::string source_;
};

}  // namespace ppp
