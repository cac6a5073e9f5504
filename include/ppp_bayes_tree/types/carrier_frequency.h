#pragma once
// Carrier frequencies [Hz] and wavelengths [m] per system and RINEX band.
// Sources: IS-GPS-200 / IS-GPS-705, GLONASS ICD 5.1, Galileo OS SIS ICD 2.1,
// BDS-SIS-ICD B1I 3.0 / B1C 1.0 / B2a 1.0, IS-QZSS-PNT, RINEX 3.05 table A23.
#include <optional>

#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// GLONASS FDMA frequency numbers k: G1 = 1602 + 0.5625 k MHz, G2 = 1246 + 0.4375 k MHz.
constexpr double kGlonassG1Base_hz = 1602.0e6;
constexpr double kGlonassG1Step_hz = 0.5625e6;
constexpr double kGlonassG2Base_hz = 1246.0e6;
constexpr double kGlonassG2Step_hz = 0.4375e6;

/// Carrier frequency of the RINEX band ('1'..'9') of a system. For GLONASS bands
/// 1 and 2 the FDMA channel number is required (nullopt without it).
/// nullopt for a band the system does not transmit.
std::optional<double> carrierFrequency_hz(GnssSystem system, char band,
                                          std::optional<int> glonass_channel = std::nullopt);
/// Wavelength c / f [m]; nullopt where the frequency is unknown.
std::optional<double> carrierWavelength_m(GnssSystem system, char band,
                                          std::optional<int> glonass_channel = std::nullopt);

}  // namespace ppp
