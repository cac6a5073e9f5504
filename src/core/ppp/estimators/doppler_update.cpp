#include "ppp_bayes_tree/ppp/estimators/doppler_update.h"

namespace ppp {

const char* dopplerOutcomeText(DopplerOutcome outcome) {
  switch (outcome) {
    case DopplerOutcome::NotTried: return "not_tried";
    case DopplerOutcome::Applied: return "applied";
    case DopplerOutcome::NoVelocity: return "no_velocity";
    case DopplerOutcome::InnovationRefused: return "innovation_refused";
  }
  return "unknown";
}

}  // namespace ppp
