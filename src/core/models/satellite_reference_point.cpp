#include "ppp_bayes_tree/models/satellite_reference_point.h"

namespace ppp {

std::string_view ephemerisReferenceName(EphemerisReference reference) {
  switch (reference) {
    case EphemerisReference::CentreOfMass: return "centre of mass";
    case EphemerisReference::AntennaPhaseCentre: return "antenna phase centre (ionosphere-free)";
    case EphemerisReference::AntennaPhaseCentreL1: return "antenna phase centre (L1)";
  }
  return "?";
}

namespace {

/// The SSR reference signals of the systems whose bands differ from GPS L1/L2
/// (satellite_reference_point.h); every other system: bands 1 and 2.
struct SsrBandRow {
  GnssSystem system;
  char first;              // AntennaPhaseCentreL1: the first frequency
  char if_band1, if_band2;  // AntennaPhaseCentre: the ionosphere-free pair
};
constexpr SsrBandRow kSsrBands[] = {
    {GnssSystem::Galileo, '1', '1', '5'},  // E1, E1/E5a
    {GnssSystem::BeiDou, '2', '2', '6'},   // B1I, B1I/B3I
};
constexpr SsrBandRow kDefaultSsrBands{GnssSystem::GPS, '1', '1', '2'};

const SsrBandRow& ssrBands(GnssSystem system) {
  for (const auto& row : kSsrBands)
    if (row.system == system) return row;
  return kDefaultSsrBands;
}

}  // namespace

char ssrFirstFrequencyBand(GnssSystem system) { return ssrBands(system).first; }

std::pair<char, char> ssrIonosphereFreeBands(GnssSystem system) {
  const SsrBandRow& row = ssrBands(system);
  return {row.if_band1, row.if_band2};
}

std::optional<Eigen::Vector3d> satelliteReferenceOffset_m(EphemerisReference reference,
                                                          const AntennaCalibration* calibration, GnssSystem system,
                                                          char band1, char band2, const IonosphereFreeCoefficients& k) {
  if (reference == EphemerisReference::CentreOfMass) return Eigen::Vector3d::Zero();
  if (calibration == nullptr) return std::nullopt;
  if (reference == EphemerisReference::AntennaPhaseCentreL1) {
    const FrequencyCalibration* f = calibration->frequency(system, ssrFirstFrequencyBand(system) - '0');
    if (f == nullptr) return std::nullopt;
    return f->pco_m;
  }
  const FrequencyCalibration* f1 = calibration->frequency(system, band1 - '0');
  const FrequencyCalibration* f2 = calibration->frequency(system, band2 - '0');
  if (f1 == nullptr || f2 == nullptr) return std::nullopt;
  return ionosphereFreeOffset(f1->pco_m, f2->pco_m, k);
}

std::optional<Eigen::Vector3d> ionosphereFreePhaseCentreOffset_m(EphemerisReference orbit_reference,
                                                                 const AntennaCalibration* calibration,
                                                                 GnssSystem system, char band1, char band2,
                                                                 const IonosphereFreeCoefficients& k) {
  if (orbit_reference == EphemerisReference::AntennaPhaseCentre) return Eigen::Vector3d::Zero();
  const auto to_if = satelliteReferenceOffset_m(EphemerisReference::AntennaPhaseCentre, calibration, system, band1,
                                                band2, k);
  if (!to_if) return std::nullopt;
  if (orbit_reference == EphemerisReference::CentreOfMass) return to_if;
  const auto to_ref = satelliteReferenceOffset_m(orbit_reference, calibration, system, band1, band2, k);
  if (!to_ref) return std::nullopt;
  return Eigen::Vector3d(*to_if - *to_ref);
}

std::optional<EphemerisReference> parseEphemerisReference(const std::string& text) {
  if (text == "com") return EphemerisReference::CentreOfMass;
  if (text == "apc" || text == "apc-if") return EphemerisReference::AntennaPhaseCentre;
  if (text == "apc-l1") return EphemerisReference::AntennaPhaseCentreL1;
  return std::nullopt;
}

}  // namespace ppp
