#pragma once
// SsrBroadcastFallback: the orbits and clocks of ppp_solve --nav F --ssr S.
// Where the SSR corrections serve (orbit and clock in force, SsrCorrectionStore's
// age limits, for at least min_ssr_satellites satellites at the instant) the
// answers are the SSR-corrected broadcast ones (BroadcastSsrEphemeris), as
// before. Where the stream's corrections are too old (a stream that stopped,
// or one of another day) the instant falls back to the broadcast records
// (BroadcastEphemerisStore) with their sigmas widened to at least
// broadcast_orbit_sigma_m / broadcast_clock_sigma_m, as the live input's
// broadcast fallback does (app/live_gnss_input.h), and the SSR biases do not
// apply there (ssr_bias_provider.h: codes as observed, the broadcast clock
// convention). Before the stream's first correction, up to the orbit age limit,
// the instant still waits for SSR (satellites are rejected, as without the
// fallback), so that a stream starting a few seconds after the observations
// changes nothing.
#include <memory>
#include <string>

#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"

namespace ppp {

struct SsrFallbackOptions {
  int min_ssr_satellites = 4;            // as LiveInputOptions::min_ssr_satellites
  double broadcast_orbit_sigma_m = 2.0;  // as LiveInputOptions (the record's URA/SISA when larger)
  double broadcast_clock_sigma_m = 2.0;
};

class SsrBroadcastFallback : public EphemerisSource {
 public:
  SsrBroadcastFallback(std::shared_ptr<const BroadcastSsrEphemeris> corrected,
                       std::shared_ptr<const BroadcastEphemerisStore> broadcast, SsrFallbackOptions options = {});

  /// True when the SSR corrections serve the instant (see above).
  bool preciseAt(const GnssTime& t) const;
  /// True when the SSR corrections serve `sat` at `t` (the SSR biases' rule).
  bool ssrInForce(const SatelliteId& sat, const GnssTime& t) const;

  EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const override;
  EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const override;
  std::string describeSource() const override;

 private:
  bool correctionsInForce(const SatelliteId& sat, const GnssTime& t) const;

  std::shared_ptr<const BroadcastSsrEphemeris> corrected_;
  std::shared_ptr<const BroadcastEphemerisStore> broadcast_;
  SsrFallbackOptions options_;
  std::optional<GnssTime> first_correction_;  // the stream's first orbit correction
  std::optional<GnssTime> last_in_force_;     // the end of the last orbit correction's validity
};

}  // namespace ppp
