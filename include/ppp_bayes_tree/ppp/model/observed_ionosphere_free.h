#pragma once
// ObservedIonosphereFree: the observed ionosphere-free (IF) code and phase [m] of
// one dual-frequency observation (the phases in metres as cycles x c / f). They
// depend on the observation alone, not on the receiver state, so an epoch's are
// computed once (observedIonosphereFree) and handed to each of its linearisations
// (PppMeasurementModel::evaluate and evaluateStart).
#include <vector>

#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"

namespace ppp {

struct ObservedIonosphereFree {
  double code_m = 0.0;
  double phase_m = 0.0;
};

ObservedIonosphereFree observedIonosphereFree(const DualFrequencyObservation& observation);

/// One per observation, in the same order (`out` cleared first).
void observedIonosphereFree(const std::vector<DualFrequencyObservation>& observations,
                            std::vector<ObservedIonosphereFree>& out);

}  // namespace ppp
