#pragma once
// Upper bounds of the numeric configuration keys (config/ppp.yaml, its ros: section,
// and the ppp_stream_node parameters): one table, by key path, consulted by
// YamlSection::number and YamlSection::integer after their lower bound, so that a
// well-typed but absurd value (smoother.fixed_lag_s: 1e9, estimator.min_satellites:
// 1000, stochastic.position.initial_sigma_m: 1e300, ros.input.correction_wait_s: 1e9)
// is refused at start-up with the key path and the allowed range, as a negative
// value already is. Each bound comes with why it is one; config/ppp.yaml states the
// same ranges in its comments. A key without an entry has only its lower bound.
#include <optional>
#include <string>

namespace ppp {

struct ConfigUpperBound {
  double max;          // largest accepted value (inclusive), in the key's unit
  const char* reason;  // why larger values are refused
};

/// The upper bound of the key at `key_path` ("smoother.fixed_lag_s"), if it has one.
std::optional<ConfigUpperBound> configUpperBound(const std::string& key_path);

/// A smallest meaningful value, for keys whose tiny positive values pass "> 0" but
/// break the estimators (an a priori sigma of 1e-300 m squares to a zero variance:
/// the covariance is singular at the first epoch).
struct ConfigLowerBound {
  double min;          // smallest accepted value (inclusive), in the key's unit
  const char* reason;  // why smaller values are refused
};

/// The lower bound of the key at `key_path`, if it has one beyond its sign.
std::optional<ConfigLowerBound> configLowerBound(const std::string& key_path);

}  // namespace ppp
