#pragma once
#include <string>

#include "ppp_bayes_tree/models/bias_provider.h"

namespace ppp_ros {

/// Where the phase information for ambiguity resolution comes from (provider
/// nullptr: none, with the reason in `source`).
struct PhaseBiasChoice {
  const ppp::BiasProvider* provider = nullptr;
  std::string source;
};

}  // namespace ppp_ros
