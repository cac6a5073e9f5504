#pragma once
// SimulatedPhaseBiases: the satellite phase biases of a simulated flight
// (simulation_config.h, errors.ambiguity.satellite_phase_biases) published as
// observable-specific biases, the way a PPP-AR analysis centre publishes phase
// OSBs consistent with its clocks (Schaer et al. 2021, J Geod 95:81): each
// satellite's carrier phase L_f [cycles] carries a constant fractional bias
// u_f (the uncalibrated phase delay), and the OSB is b_f = u_f * lambda_f [m]
// so that corrected = observed - bias (Bias-SINEX sign) removes it. The
// simulated codes carry no satellite bias (the clocks are those of the IF code):
// the code OSB is 0 for every simulated satellite. Satellites without a drawn
// UPD (the option off) have none: nullopt answers, and the upd() is zero.
#include <map>

#include "ppp_bayes_tree/models/bias_provider.h"

namespace ppp {

class SimulatedPhaseBiases : public BiasProvider {
 public:
  struct Upd {
    double l1_cycles = 0.0, l2_cycles = 0.0;
  };
  /// Sets a satellite's UPD on bands 1 and 2 with their wavelengths [m].
  void set(const SatelliteId& sat, double l1_cycles, double l2_cycles, double lambda1_m, double lambda2_m);
  /// The UPD added to the simulated phases (zero when none was drawn).
  Upd upd(const SatelliteId& sat) const;
  bool empty() const { return biases_.empty(); }

  BiasAnswer codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  BiasAnswer phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  std::string describeSource() const override { return "simulated satellite phase biases (OSB)"; }

 private:
  struct Entry {
    Upd upd;
    double lambda1_m = 0.0, lambda2_m = 0.0;
  };
  std::map<SatelliteId, Entry> biases_;
};

}  // namespace ppp
