#pragma once
// Satellite reference point: the one place that turns the point an orbit
// refers to (EphemerisReference) into satellite antenna offsets (PCO, body
// frame x/y/z of the nominal yaw attitude, satellite_attitude.h).
//
// Three conventions:
//   CentreOfMass          precise SP3 files, broadcast orbits, "SSRC" streams;
//   AntennaPhaseCentre    the ionosphere-free phase centre of the processed pair
//                         (what ppp_ssr_encode --reference apc writes);
//   AntennaPhaseCentreL1  the phase centre of the FIRST frequency (GPS/QZSS L1,
//                         Galileo E1, GLONASS G1): the IGS "SSRA" streams. Checked
//                         on SSRA03IGS0 against IGS ultra-rapid orbits
//                         (ppp_ssr_check, evaluation/ssr_check.h): the GPS III
//                         satellites, whose L1 and L2 PCOs in igs20.atx differ by
//                         0.50 m, agree to 5 cm with the L1 PCO and are 0.78 m
//                         off radially with the ionosphere-free one.
//
// The measurement model needs the ionosphere-free phase centre of its pair:
//   x_IF = x_orbit + R_body (PCO_IF - PCO_ref)
// with PCO_ref = 0 (centre of mass), PCO_IF (then nothing to add, and no ANTEX
// entry needed) or PCO_L1. For an L1 orbit the difference needs the satellite's
// ANTEX entry; a satellite without one (e.g. Galileo with a GPS-only ANTEX file)
// gets a zero difference (nullopt here; the model counts the satellite-epochs
// and says so in the run notes): exact when its first- and second-frequency PCOs
// are equal, otherwise in error by the IF - L1 difference, which without a
// calibration cannot be known (0.78 m radially for a GPS III satellite).
#include <optional>
#include <string>

#include <Eigen/Core>

#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/types/antenna_calibration.h"

namespace ppp {

/// The RINEX band of the first frequency an L1 stream refers to: '1' (L1, E1,
/// G1, SBAS L1), BeiDou '2' (B1I, the RTCM SSR BeiDou signal of reference).
char ssrFirstFrequencyBand(GnssSystem system);

/// The two bands whose ionosphere-free phase centre an SSR stream at the
/// AntennaPhaseCentre refers to when written by ppp_ssr_encode: L1/L2, Galileo E1/E5a.
std::pair<char, char> ssrIonosphereFreeBands(GnssSystem system);

/// Offset [m, body x/y/z] of the point `reference` from the centre of mass, for
/// the pair (band1, band2) with IF weights `k`: zero, PCO_IF(band1, band2) or
/// PCO_L1. nullopt: `calibration` is null or lacks a frequency it needs.
std::optional<Eigen::Vector3d> satelliteReferenceOffset_m(EphemerisReference reference,
                                                          const AntennaCalibration* calibration, GnssSystem system,
                                                          char band1, char band2, const IonosphereFreeCoefficients& k);

/// What the measurement model adds [m, body x/y/z] to an orbit at
/// `orbit_reference` to reach the ionosphere-free phase centre of (band1, band2):
/// PCO_IF - PCO_ref. Zero, without a calibration, for an AntennaPhaseCentre
/// orbit. nullopt: a calibration it needs is missing.
std::optional<Eigen::Vector3d> ionosphereFreePhaseCentreOffset_m(EphemerisReference orbit_reference,
                                                                 const AntennaCalibration* calibration,
                                                                 GnssSystem system, char band1, char band2,
                                                                 const IonosphereFreeCoefficients& k);

/// Command-line / configuration spellings: "com", "apc" or "apc-if"
/// (ionosphere-free), "apc-l1" (IGS SSRA); nullopt otherwise.
std::optional<EphemerisReference> parseEphemerisReference(const std::string& text);

}  // namespace ppp
