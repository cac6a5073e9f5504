#pragma once
// The broadcast fallback rule of SSR-corrected broadcast products, one for the
// offline run (ppp_solve --nav F --ssr S: SsrBroadcastFallback) and the live
// input (LiveGnssInput): the SSR-corrected answers serve while SSR orbit and
// clock corrections are in force for at least min_ssr_satellites satellites;
// otherwise (corrections missing, or too old after a stream stopped) the
// broadcast records serve, their orbit and clock sigmas widened to at least
// orbit_sigma_m / clock_sigma_m (the record's URA/SISA when larger), and the
// SSR biases do not apply there (codes as observed, as the broadcast clocks
// expect). With the fallback off, the SSR-corrected answers always serve and a
// satellite without corrections is rejected.
// The keys are those of `ssr:` in config/ppp.yaml (SsrStreamOptions::fallback).
// What each path counts as "in force": the offline run, the satellites of the
// recording with orbit and clock corrections in force at the instant; the live
// input, the epoch's satellites with an SSR-corrected state at its time.
#include <string_view>

#include "ppp_bayes_tree/models/ephemeris_source.h"

namespace ppp {

struct BroadcastFallbackOptions {
  /// `ssr.broadcast_fallback`: corrections missing or too old -> broadcast (default true).
  bool enabled = true;
  /// `ssr.min_ssr_satellites`: SSR serves with orbit+clock in force for at least this many satellites (default 4).
  int min_ssr_satellites = 4;
  /// `ssr.broadcast_orbit_sigma_m` / `ssr.broadcast_clock_sigma_m`: sigmas of broadcast answers in fallback [m]
  /// (default 2.0 and 2.0: GPS URA and broadcast clock errors are metre level).
  double orbit_sigma_m = 2.0;
  double clock_sigma_m = 2.0;
};

/// Which orbits and clocks serve an instant of an SSR run.
enum class SsrOrbitClockChoice {
  Ssr,                // the SSR-corrected broadcast answers
  BroadcastFallback,  // the broadcast records, sigmas widened
};
std::string_view ssrOrbitClockChoiceName(SsrOrbitClockChoice choice);  // "SSR", "broadcast fallback"

/// The rule: `satellites_in_force` satellites have SSR orbit and clock in force
/// (callers may stop counting at options.min_ssr_satellites).
SsrOrbitClockChoice chooseSsrOrBroadcast(int satellites_in_force, const BroadcastFallbackOptions& options);

/// A broadcast answer served in fallback: its sigma at least the options' one.
void widenForFallback(EphemerisAnswer<EphemerisClock>& answer, const BroadcastFallbackOptions& options);
void widenForFallback(EphemerisAnswer<EphemerisOrbit>& answer, const BroadcastFallbackOptions& options);

}  // namespace ppp
