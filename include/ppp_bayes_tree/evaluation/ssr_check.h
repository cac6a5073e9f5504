#pragma once
// SSR check: SSR-corrected broadcast orbits and clocks compared with a precise
// SP3 file, as a user checks a correction stream (ppp_ssr_check).
//
// At every SSR orbit epoch inside the SP3 span, for every satellite with both:
//  - orbit: the 3D difference (and its radial/along/cross parts) between the
//    corrected broadcast position and the SP3 position. SP3 positions are
//    centre-of-mass: with an antenna-phase-centre stream the SP3 position is
//    moved to the APC by the satellite's ionosphere-free PCO from ANTEX (nominal
//    yaw attitude), so that like is compared with like; without an ANTEX entry
//    the satellite is compared as is and the handling says so.
//  - clock: the difference corrected - SP3 [ns], minus the mean over the
//    satellites of the epoch (each product has its own clock datum).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// Which phase centre an APC stream's orbits refer to. The IGS SSRA streams
/// refer to the L1 (E1) phase centre: checked on SSRA03IGS0 against IGS
/// ultra-rapid orbits, GPS III satellites (L1 and L2 PCO 0.50 m apart in
/// igs20.atx) agree to 5 cm with the L1 PCO and are 0.78 m off radially with the
/// ionosphere-free PCO, while satellites with equal L1/L2 PCOs agree either way.
/// (The same conventions as EphemerisReference::AntennaPhaseCentreL1 /
/// AntennaPhaseCentre, models/satellite_reference_point.h.)
enum class SsrApcFrequency { FirstFrequency, IonosphereFree };

struct SsrCheckRequest {
  std::vector<std::string> nav;
  std::string ssr;
  std::string sp3;
  /// Optional RINEX clock files: the clocks compared with them instead of the SP3 clocks.
  std::vector<std::string> clk;
  std::optional<std::string> atx;
  /// The stream's reference point; nullopt: from the stream name (SSRA: APC L1,
  /// SSRC: centre of mass), else APC L1.
  std::optional<EphemerisReference> reference;
  /// For an antenna-phase-centre reference: which phase centre, overriding the
  /// one `reference` names (ppp_ssr_check --apc l1|if); nullopt: as `reference` says.
  std::optional<SsrApcFrequency> apc;
  /// Systems compared (those the SP3 and the broadcast model have).
  std::vector<GnssSystem> systems{GnssSystem::GPS, GnssSystem::Galileo, GnssSystem::GLONASS, GnssSystem::QZSS};
};

struct SsrCheckSatellite {
  SatelliteId satellite;
  std::size_t epochs = 0;
  double orbit_rms_3d_m = 0.0;
  double radial_rms_m = 0.0, along_rms_m = 0.0, cross_rms_m = 0.0;
  std::size_t clock_epochs = 0;
  double clock_rms_ns = 0.0;
  bool pco_applied = false;
};

struct SsrCheckResult {
  std::vector<SsrCheckSatellite> satellites;
  std::size_t satellite_epochs = 0;
  double orbit_rms_3d_m = 0.0;
  double clock_rms_ns = 0.0;
  std::size_t clock_satellite_epochs = 0;
  EphemerisReference reference = EphemerisReference::AntennaPhaseCentreL1;  // as used
  std::string reference_handling;  // one line for people
  std::vector<std::string> notes;  // decoding summary, problems, exclusions
  /// "orbit 3D RMS <m> m, clock RMS <ns> ns, <N> satellite-epochs"
  std::string lastLine() const;
};

/// Runs the check (throws FileOpenError / ParseError on unreadable inputs).
SsrCheckResult checkSsrAgainstSp3(const SsrCheckRequest& request);
/// Per-satellite table and notes, then the last line.
std::string formatSsrCheck(const SsrCheckResult& result);

}  // namespace ppp
