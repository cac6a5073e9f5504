#include "ppp_bayes_tree/ppp/pipeline/solution_epoch.h"

namespace ppp {

const char* solutionStatusName(SolutionStatus status) {
  switch (status) {
    case SolutionStatus::NoSolution: return "no-solution";
    case SolutionStatus::Single: return "single";
    case SolutionStatus::PppFloat: return "ppp-float";
    case SolutionStatus::PppFixed: return "ppp-fixed";
  }
  return "unknown";
}

int rtklibQuality(SolutionStatus status) {
  switch (status) {
    case SolutionStatus::NoSolution: return 0;
    case SolutionStatus::Single: return 5;
    case SolutionStatus::PppFloat: return 6;
    case SolutionStatus::PppFixed: return 1;
  }
  return 0;
}

}  // namespace ppp
