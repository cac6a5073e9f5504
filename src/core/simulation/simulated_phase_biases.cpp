#include "ppp_bayes_tree/simulation/simulated_phase_biases.h"

namespace ppp {

void SimulatedPhaseBiases::set(const SatelliteId& sat, double l1_cycles, double l2_cycles, double lambda1_m,
                               double lambda2_m) {
  biases_[sat] = Entry{Upd{l1_cycles, l2_cycles}, lambda1_m, lambda2_m};
}

SimulatedPhaseBiases::Upd SimulatedPhaseBiases::upd(const SatelliteId& sat) const {
  const auto it = biases_.find(sat);
  return it == biases_.end() ? Upd{} : it->second.upd;
}

BiasAnswer SimulatedPhaseBiases::codeBias(const SatelliteId& sat, const ObservationCode& /*code*/,
                                          const GnssTime& /*t*/) const {
  BiasAnswer a;
  if (biases_.count(sat)) a.value_m = 0.0;  // unbounded validity
  return a;
}

BiasAnswer SimulatedPhaseBiases::phaseBias(const SatelliteId& sat, const ObservationCode& code,
                                           const GnssTime& /*t*/) const {
  BiasAnswer a;
  const auto it = biases_.find(sat);
  if (it == biases_.end()) return a;
  if (code.band == '1') a.value_m = it->second.upd.l1_cycles * it->second.lambda1_m;
  if (code.band == '2' || code.band == '5') a.value_m = it->second.upd.l2_cycles * it->second.lambda2_m;
  return a;
}

}  // namespace ppp
