#include "ppp_bayes_tree/ppp/estimators/estimator_epoch_result.h"

namespace ppp {

std::string toString(EpochStatus status) {
  switch (status) {
    case EpochStatus::Ok: return "ok";
    case EpochStatus::NoSolution: return "no_solution";
    case EpochStatus::Failed: return "failed";
  }
  return "unknown";
}

std::string toString(AmbiguityState state) {
  switch (state) {
    case AmbiguityState::Float: return "float";
    case AmbiguityState::Fixed: return "fixed";
  }
  return "unknown";
}

}  // namespace ppp
