#pragma once
// Fuzz entry for the RINEX navigation reader: bytes -> memoryLineSource ->
// readRinexNav, then every decoded record through the ephemeris store and the
// broadcast models (Kepler iterations, GLONASS integration) at a few instants.
// Only the documented exceptions (ParseError, FileOpenError) are caught.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"

namespace ppp::fuzz {

inline void fuzzRinexNav(const std::uint8_t* data, std::size_t size) {
  auto source = memoryLineSource(std::string(reinterpret_cast<const char*>(data), size), "fuzz.nav");
  try {
    const NavData nav = readRinexNav(*source);
    EphemerisSelectionOptions options;
    options.galileo = GalileoPreference::Any;
    BroadcastEphemerisStore store(options);
    store.add(nav);
    volatile double sink = 0.0;
    auto use = [&](const BroadcastState& s) {
      sink = sink + s.position_ecef_m.sum() + s.velocity_ecef_mps.sum() + s.clock_bias_s;
    };
    for (const auto& e : nav.gps) {
      for (double dt : {-7200.0, 0.0, 900.0}) use(satelliteState(e, e.orbit.toe + dt));
      if (auto s = store.state(e.satellite, e.orbit.toe + 60.0)) use(*s.state);
    }
    for (const auto& e : nav.galileo) {
      for (double dt : {-7200.0, 0.0, 900.0}) use(satelliteState(e, e.orbit.toe + dt));
      if (auto s = store.state(e.satellite, e.orbit.toe)) use(*s.state);
    }
    for (const auto& e : nav.glonass) {
      for (double dt : {-900.0, 0.0, 1800.0}) use(satelliteState(e, e.tb + dt));
      if (auto s = store.state(e.satellite, e.tb + 30.0)) use(*s.state);
    }
    (void)nav.report.summary();
  } catch (const ParseError&) {
  } catch (const FileOpenError&) {
  }
}

}  // namespace ppp::fuzz
