#include "ppp_bayes_tree/ppp/model/observed_ionosphere_free.h"

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

ObservedIonosphereFree observedIonosphereFree(const DualFrequencyObservation& o) {
  const IonosphereFreeCoefficients k = ionosphereFreeCoefficients(o.frequency1_hz, o.frequency2_hz);
  ObservedIonosphereFree out;
  out.code_m = ionosphereFree(o.code1_m, o.code2_m, k);
  out.phase_m = ionosphereFree(o.phase1_cycles * kSpeedOfLight_mps / o.frequency1_hz,
                               o.phase2_cycles * kSpeedOfLight_mps / o.frequency2_hz, k);
  return out;
}

void observedIonosphereFree(const std::vector<DualFrequencyObservation>& observations,
                            std::vector<ObservedIonosphereFree>& out) {
  out.clear();
  out.reserve(observations.size());
  for (const DualFrequencyObservation& o : observations) out.push_back(observedIonosphereFree(o));
}

}  // namespace ppp
