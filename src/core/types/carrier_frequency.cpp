#include "ppp_bayes_tree/types/carrier_frequency.h"

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {
constexpr double kL1_hz = 1575.42e6;   // GPS L1, Galileo E1, QZSS L1, BDS B1C, SBAS L1
constexpr double kL2_hz = 1227.60e6;   // GPS L2, QZSS L2
constexpr double kL5_hz = 1176.45e6;   // GPS L5, Galileo E5a, BDS B2a, QZSS L5, SBAS L5, NavIC L5
constexpr double kE5b_hz = 1207.140e6; // Galileo E5b, BDS B2b/B2I
constexpr double kE5_hz = 1191.795e6;  // Galileo E5 AltBOC, BDS B2a+b
constexpr double kE6_hz = 1278.75e6;   // Galileo E6, QZSS LEX/L6
constexpr double kB1I_hz = 1561.098e6; // BDS B1I
constexpr double kB3_hz = 1268.52e6;   // BDS B3I
constexpr double kG1a_hz = 1600.995e6; // GLONASS CDMA L1OC
constexpr double kG2a_hz = 1248.06e6;  // GLONASS CDMA L2OC
constexpr double kG3_hz = 1202.025e6;  // GLONASS CDMA L3OC
constexpr double kS_hz = 2492.028e6;   // NavIC S band
}  // namespace

std::optional<double> carrierFrequency_hz(GnssSystem system, char band,
                                          std::optional<int> glonass_channel) {
  switch (system) {
    case GnssSystem::GPS:
      if (band == '1') return kL1_hz;
      if (band == '2') return kL2_hz;
      if (band == '5') return kL5_hz;
      break;
    case GnssSystem::GLONASS:
      if (band == '1' || band == '2') {
        if (!glonass_channel || *glonass_channel < -7 || *glonass_channel > 13) return std::nullopt;
        return band == '1' ? kGlonassG1Base_hz + kGlonassG1Step_hz * *glonass_channel
                           : kGlonassG2Base_hz + kGlonassG2Step_hz * *glonass_channel;
      }
      if (band == '3') return kG3_hz;
      if (band == '4') return kG1a_hz;
      if (band == '6') return kG2a_hz;
      break;
    case GnssSystem::Galileo:
      if (band == '1') return kL1_hz;
      if (band == '5') return kL5_hz;
      if (band == '7') return kE5b_hz;
      if (band == '8') return kE5_hz;
      if (band == '6') return kE6_hz;
      break;
    case GnssSystem::BeiDou:
      if (band == '1') return kL1_hz;
      if (band == '2') return kB1I_hz;
      if (band == '5') return kL5_hz;
      if (band == '7') return kE5b_hz;
      if (band == '8') return kE5_hz;
      if (band == '6') return kB3_hz;
      break;
    case GnssSystem::QZSS:
      if (band == '1') return kL1_hz;
      if (band == '2') return kL2_hz;
      if (band == '5') return kL5_hz;
      if (band == '6') return kE6_hz;
      break;
    case GnssSystem::SBAS:
      if (band == '1') return kL1_hz;
      if (band == '5') return kL5_hz;
      break;
    case GnssSystem::IRNSS:
      if (band == '5') return kL5_hz;
      if (band == '9') return kS_hz;
      break;
  }
  return std::nullopt;
}

std::optional<double> carrierWavelength_m(GnssSystem system, char band,
                                          std::optional<int> glonass_channel) {
  const auto f = carrierFrequency_hz(system, band, glonass_channel);
  if (!f) return std::nullopt;
  return kSpeedOfLight_mps / *f;
}

}  // namespace ppp
