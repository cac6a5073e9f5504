#pragma once
// BiasProvider: satellite code and phase biases per signal (observable-specific
// biases, OSB) that align the observations with the clock product's reference:
// corrected = observed - bias (Bias-SINEX 1.00 sign convention), in metres.
// Bias-SINEX files today (SinexBiasProvider); SSR bias messages later, and the
// wide-lane satellite biases of integer-clock products.
//
// Each answer says over which interval it stays the answer, so that callers
// can cache it (the signal selector asks once per satellite and signal, not
// once per epoch).
#include <optional>
#include <string>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct BiasAnswer {
  std::optional<double> value_m;  // nullopt: the provider has no bias for this signal
  /// The same answer holds over [valid_from, valid_until] (nullopt = unbounded).
  /// An absent bias holds for the asked instant only.
  std::optional<GnssTime> valid_from, valid_until;
  /// false: the provider has no say at this instant, e.g. SSR biases while the
  /// SSR orbit and clock corrections are too old and broadcast orbits and clocks
  /// serve (their clocks refer to the codes as observed): the signal is used
  /// without a bias and none is required.
  bool applies = true;
};

class BiasProvider {
 public:
  virtual ~BiasProvider() = default;
  /// Satellite code bias of `code` at `t` [m].
  virtual BiasAnswer codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const = 0;
  /// Satellite phase bias of `code` at `t` [m] (not used by the float IF model:
  /// the arc biases absorb it; integer ambiguity resolution will need it).
  virtual BiasAnswer phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const = 0;
  /// For run notes, e.g. "COD0OPSFIN_..._OSB.BIA.gz (Bias-SINEX OSB)".
  virtual std::string describeSource() const = 0;
};

}  // namespace ppp
