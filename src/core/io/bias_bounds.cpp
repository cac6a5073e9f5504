#include "ppp_bayes_tree/io/bias_bounds.h"

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

namespace {

std::string number(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

const char* kindName(BiasKind kind) { return kind == BiasKind::Phase ? "phase bias" : "code bias"; }

double bound_ns(BiasKind kind) { return kind == BiasKind::Phase ? biasBounds().phase_ns : biasBounds().code_ns; }

}  // namespace

std::optional<std::string> biasBeyondBound(BiasKind kind, double value, bool in_cycles) {
  const double bound = in_cycles ? bound_ns(kind) * 1e-9 * biasBounds().highest_carrier_hz : bound_ns(kind);
  if (std::isfinite(value) && std::abs(value) <= bound) return std::nullopt;
  const char* unit = in_cycles ? " cycles" : " ns";
  return std::string(kindName(kind)) + " " + number(value) + unit + " beyond the bound of " + number(bound) + unit;
}

std::optional<std::string> biasBeyondBound_m(BiasKind kind, double value_m) {
  const double bound_m = bound_ns(kind) * 1e-9 * kSpeedOfLight_mps;
  if (std::isfinite(value_m) && std::abs(value_m) <= bound_m) return std::nullopt;
  return std::string(kindName(kind)) + " " + number(value_m) + " m beyond the bound of " + number(bound_m) + " m (" +
         number(bound_ns(kind)) + " ns)";
}

std::optional<std::string> wideLaneBiasBeyondBound(double value_cycles) {
  const double bound = biasBounds().wide_lane_cycles;
  if (std::isfinite(value_cycles) && std::abs(value_cycles) <= bound) return std::nullopt;
  return "wide-lane bias " + number(value_cycles) + " cycles beyond the bound of " + number(bound) + " cycles";
}

}  // namespace ppp
