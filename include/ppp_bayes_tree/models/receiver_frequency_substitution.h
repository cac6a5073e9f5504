#pragma once
// Receiver antenna frequency substitution: which GPS calibration stands in for a
// frequency of another system that a receiver antenna block (ANTEX) does not
// calibrate. Many receiver calibrations (all of igs05.atx, most type means of the
// IGS files) hold G01/G02 only, while the antenna's phase centre for E1/E5a is
// within millimetres of its L1/L2 one; leaving the receiver PCO/PCV out instead
// puts its whole size (about 10 cm up for a choke ring) into that system's ranges
// and biases its ambiguities.
//
// Practice and references:
//  - igs14.atx header: "If no corrections for the GLONASS frequencies are
//    available, the values for the GPS frequencies are used within the IGS
//    instead" (G01 for R01, G02 for R02);
//  - MGEX analysis (e.g. CODE's multi-GNSS processing, Prange et al. 2017,
//    J. Geod. 91(4)) uses the GPS L1/L2 receiver values for Galileo E1/E5a when
//    the antenna has no Galileo calibration;
//  - igs20.atx header, in contrast: "If no corrections for the GLONASS or
//    GALILEO frequencies are available, do not use those observations": the
//    `None` policy (the frequency stays uncalibrated and the receiver_antenna
//    policy decides).
//
// The table maps each non-GPS ANTEX frequency to the GPS frequencies nearest in
// carrier frequency, in order of preference (the first one the block holds is
// used): E1 -> G01 (the same 1575.42 MHz), E5a -> G05 (the same 1176.45 MHz),
// else G02 (L2), E5b / E6 -> G02, R01 -> G01, R02 -> G02, and likewise BeiDou and
// QZSS. GPS frequencies are never substituted.
#include <array>
#include <string>
#include <string_view>

#include "ppp_bayes_tree/types/antenna_calibration.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// measurement_model.corrections.receiver_frequency_substitution.
enum class ReceiverFrequencySubstitution {
  Gps,   // a missing non-GPS frequency takes the GPS calibration of the table
  None,  // a missing frequency stays missing
};
std::string_view receiverFrequencySubstitutionName(ReceiverFrequencySubstitution policy);

/// One row of the substitution table.
struct GpsStandIn {
  GnssSystem system = GnssSystem::Galileo;
  int frequency = 1;                 // ANTEX frequency number (E05 -> 5)
  std::string_view signal;           // "E5a"
  double carrier_mhz = 0.0;          // the frequency's carrier [MHz]
  std::array<int, 2> gps_frequencies{};  // GPS ANTEX frequency numbers, preferred first; 0 = none
};

/// The table row of a non-GPS frequency; nullptr for GPS and for frequencies
/// without one (e.g. the GLONASS CDMA frequencies).
const GpsStandIn* gpsStandIn(GnssSystem system, int frequency);
/// Every row (for documentation and tests).
const std::array<GpsStandIn, 17>& gpsStandInTable();
/// "L1", "L2", "L5" for GPS ANTEX frequencies 1, 2, 5; "G0n" otherwise.
std::string gpsSignalName(int frequency);

/// A receiver calibration of one frequency, possibly a GPS stand-in.
struct ReceiverFrequencyLookup {
  const FrequencyCalibration* calibration = nullptr;  // nullptr: missing
  bool substituted = false;  // calibration is the GPS frequency standing in
};

/// The receiver calibration of `frequency` of `system`: the block's own when it
/// has one, else (policy Gps) the first GPS frequency of the table the block
/// holds, else missing.
ReceiverFrequencyLookup receiverFrequencyCalibration(const AntennaCalibration& receiver, GnssSystem system,
                                                     int frequency, ReceiverFrequencySubstitution policy);

/// The run's note for a frequency pair with at least one substitution, e.g.
/// "receiver antenna ASH701945E_M SCIS: no Galileo calibration, GPS L1/L2 values
/// used for E1/E5a (...receiver_frequency_substitution: gps)".
std::string receiverSubstitutionNote(const AntennaCalibration& receiver, GnssSystem system, int frequency1,
                                     const ReceiverFrequencyLookup& lookup1, int frequency2,
                                     const ReceiverFrequencyLookup& lookup2);

}  // namespace ppp
