#include "ppp_bayes_tree/ppp/screening/solution_integrity.h"

namespace ppp {

std::string toString(SolutionIntegrity integrity) {
  switch (integrity) {
    case SolutionIntegrity::Unchecked: return "unchecked";
    case SolutionIntegrity::Consistent: return "consistent";
    case SolutionIntegrity::Inconsistent: return "inconsistent";
  }
  return "unknown";
}

}  // namespace ppp
