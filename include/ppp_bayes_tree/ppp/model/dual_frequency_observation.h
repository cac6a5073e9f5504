#pragma once
// DualFrequencyObservation: the two code and two phase observables of one
// satellite at one epoch, chosen for the ionosphere-free (IF) combination
// (GPS L1/L2, GLONASS G1/G2, Galileo E1/E5a, BeiDou B1I/B3I). Produced by signal selection from a RINEX epoch;
// consumed by cycle-slip detection / arc tracking and by the measurement model.
#include <cstdint>
#include <optional>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct DualFrequencyObservation {
  SatelliteId satellite;
  GnssTime time;  // receiver time tag of the epoch (GPST)
  // Signals used (e.g. C1W/L1C and C2W/L2W).
  ObservationCode code1, code2, phase1, phase2;
  // The pair's carrier frequencies [Hz]: per system, and per satellite for
  // GLONASS FDMA (from its frequency channel).
  double frequency1_hz = 0.0;
  double frequency2_hz = 0.0;
  // Factor on the code sigma of the IF code (SystemSignalPriority::code_sigma_factor).
  double code_sigma_factor = 1.0;
  // Pseudoranges [m], already aligned to the clock product's code reference
  // (Bias-SINEX OSB when given, otherwise the product convention).
  double code1_m = 0.0;
  double code2_m = 0.0;
  // The OSB [m] subtracted from each code (observed - OSB, Bias-SINEX 1.00);
  // nullopt when none was applied (no bias file, or no row for the code).
  std::optional<double> code1_osb_m;
  std::optional<double> code2_osb_m;
  // Carrier phases [cycles] as observed (RINEX sign convention), with the
  // RINEX 3 SYS / PHASE SHIFT correction applied where given.
  double phase1_cycles = 0.0;
  double phase2_cycles = 0.0;
  // Receiver loss-of-lock indicator bit 0 (cycle slip possible) per frequency,
  // and bit 1 (half-cycle ambiguity) on either.
  bool loss_of_lock1 = false;
  bool loss_of_lock2 = false;
  bool half_cycle_ambiguity = false;
  std::optional<double> cn0_1_dbhz;  // signal strength where the file gives it
};

/// Identifier of one continuous carrier-phase arc of one satellite: a new arc
/// starts with a new satellite, after a detected cycle slip, or after a data gap.
/// Ids are unique over a whole run (they key the smoother's bias landmarks).
using ArcId = std::uint32_t;

}  // namespace ppp
