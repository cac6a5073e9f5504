#include "ppp_bayes_tree/io/epoch_time_guard.h"

namespace ppp {

std::string text(TimeDropReason reason) {
  switch (reason) {
    case TimeDropReason::Duplicate: return "duplicate stamp";
    case TimeDropReason::OutOfOrder: return "out of order";
    case TimeDropReason::UnconfirmedJump: return "isolated time jump (not confirmed by the following epochs)";
  }
  return "unknown";
}

}  // namespace ppp
