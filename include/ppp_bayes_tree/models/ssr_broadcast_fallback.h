#pragma once
// SsrBroadcastFallback: the orbits and clocks of ppp_solve --nav F --ssr S.
// Each instant is decided by the broadcast fallback rule the live input uses as
// well (models/broadcast_fallback.h: chooseSsrOrBroadcast over the satellites
// of the recording with orbit and clock corrections in force at the instant,
// SsrCorrectionStore's age limits): the SSR-corrected broadcast answers
// (BroadcastSsrEphemeris), or the broadcast records (BroadcastEphemerisStore)
// with their sigmas widened, where the stream's corrections are too old (a
// stream that stopped, or one of another day); the SSR biases do not apply
// there (ssr_bias_provider.h: codes as observed, the broadcast clock
// convention). Before the stream's first correction, up to the orbit age limit,
// the instant still waits for SSR (satellites are rejected, as without the
// fallback), so that a stream starting a few seconds after the observations
// changes nothing.
#include <memory>
#include <string>

#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/models/broadcast_fallback.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"

namespace ppp {

class SsrBroadcastFallback : public EphemerisSource {
 public:
  SsrBroadcastFallback(std::shared_ptr<const BroadcastSsrEphemeris> corrected,
                       std::shared_ptr<const BroadcastEphemerisStore> broadcast, BroadcastFallbackOptions options = {});

  const BroadcastFallbackOptions& options() const { return options_; }
  /// True when the SSR corrections serve the instant (see above).
  bool preciseAt(const GnssTime& t) const;
  /// True when the SSR corrections serve `sat` at `t` (the SSR biases' rule).
  bool ssrInForce(const SatelliteId& sat, const GnssTime& t) const;

  EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const override;
  EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const override;
  std::string describeSource() const override;

 private:
  bool correctionsInForce(const SatelliteId& sat, const GnssTime& t) const;
  /// Satellites with orbit and clock in force at `t`, counted up to min_ssr_satellites.
  int satellitesInForce(const GnssTime& t) const;

  std::shared_ptr<const BroadcastSsrEphemeris> corrected_;
  std::shared_ptr<const BroadcastEphemerisStore> broadcast_;
  BroadcastFallbackOptions options_;
  std::optional<GnssTime> first_correction_;  // the stream's first orbit correction
  std::optional<GnssTime> last_in_force_;     // the end of the last orbit correction's validity
};

}  // namespace ppp
