#include "ppp_bayes_tree/models/broadcast_fallback.h"

#include <algorithm>

namespace ppp {

std::string_view ssrOrbitClockChoiceName(SsrOrbitClockChoice choice) {
  switch (choice) {
    case SsrOrbitClockChoice::Ssr: return "SSR";
    case SsrOrbitClockChoice::BroadcastFallback: return "broadcast fallback";
  }
  return "unknown";
}

SsrOrbitClockChoice chooseSsrOrBroadcast(int satellites_in_force, const BroadcastFallbackOptions& options) {
  if (!options.enabled || satellites_in_force >= options.min_ssr_satellites) return SsrOrbitClockChoice::Ssr;
  return SsrOrbitClockChoice::BroadcastFallback;
}

void widenForFallback(EphemerisAnswer<EphemerisClock>& answer, const BroadcastFallbackOptions& options) {
  if (answer.ok()) answer.value->clock_sigma_m = std::max(answer.value->clock_sigma_m.value_or(0.0), options.clock_sigma_m);
}

void widenForFallback(EphemerisAnswer<EphemerisOrbit>& answer, const BroadcastFallbackOptions& options) {
  if (answer.ok())
    answer.value->position_sigma_m = std::max(answer.value->position_sigma_m.value_or(0.0), options.orbit_sigma_m);
}

}  // namespace ppp
