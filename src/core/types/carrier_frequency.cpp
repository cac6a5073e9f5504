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

namespace {

/// CDMA carriers: one row per system and RINEX band (RINEX 3.05 table A23).
struct CarrierRow {
  GnssSystem system;
  char band;
  double frequency_hz;
};

constexpr CarrierRow kCarriers[] = {
    // clang-format off
    {GnssSystem::GPS, '1', kL1_hz}, {GnssSystem::GPS, '2', kL2_hz}, {GnssSystem::GPS, '5', kL5_hz},
    {GnssSystem::GLONASS, '3', kG3_hz}, {GnssSystem::GLONASS, '4', kG1a_hz}, {GnssSystem::GLONASS, '6', kG2a_hz},
    {GnssSystem::Galileo, '1', kL1_hz}, {GnssSystem::Galileo, '5', kL5_hz}, {GnssSystem::Galileo, '7', kE5b_hz},
        {GnssSystem::Galileo, '8', kE5_hz}, {GnssSystem::Galileo, '6', kE6_hz},
    {GnssSystem::BeiDou, '1', kL1_hz}, {GnssSystem::BeiDou, '2', kB1I_hz}, {GnssSystem::BeiDou, '5', kL5_hz},
        {GnssSystem::BeiDou, '7', kE5b_hz}, {GnssSystem::BeiDou, '8', kE5_hz}, {GnssSystem::BeiDou, '6', kB3_hz},
    {GnssSystem::QZSS, '1', kL1_hz}, {GnssSystem::QZSS, '2', kL2_hz}, {GnssSystem::QZSS, '5', kL5_hz},
        {GnssSystem::QZSS, '6', kE6_hz},
    {GnssSystem::SBAS, '1', kL1_hz}, {GnssSystem::SBAS, '5', kL5_hz},
    {GnssSystem::IRNSS, '5', kL5_hz}, {GnssSystem::IRNSS, '9', kS_hz},
    // clang-format on
};

}  // namespace

std::optional<double> carrierFrequency_hz(GnssSystem system, char band,
                                          std::optional<int> glonass_channel) {
  // GLONASS FDMA G1/G2: a different carrier per frequency channel, not a table row.
  if (system == GnssSystem::GLONASS && (band == '1' || band == '2')) {
    if (!glonass_channel || *glonass_channel < -7 || *glonass_channel > 13) return std::nullopt;
    return band == '1' ? kGlonassG1Base_hz + kGlonassG1Step_hz * *glonass_channel
                       : kGlonassG2Base_hz + kGlonassG2Step_hz * *glonass_channel;
  }
  for (const auto& row : kCarriers)
    if (row.system == system && row.band == band) return row.frequency_hz;
  return std::nullopt;
}

std::optional<double> carrierWavelength_m(GnssSystem system, char band,
                                          std::optional<int> glonass_channel) {
  const auto f = carrierFrequency_hz(system, band, glonass_channel);
  if (!f) return std::nullopt;
  return kSpeedOfLight_mps / *f;
}

}  // namespace ppp
