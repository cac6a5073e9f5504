#pragma once
// EphemerisSource: where the measurement model gets a satellite's orbit and
// clock. One interface answers for one satellite at one instant (GPST):
//   - the clock offset (and its rate when the source has one), with its sigma;
//   - the position and velocity (ECEF), with its sigma, and the POINT the
//     position refers to: the centre of mass (precise SP3 files, broadcast
//     orbits) or the antenna phase centre (SSR streams such as IGS SSRA): with
//     the antenna phase centre the satellite antenna offset (PCO) is already in
//     the orbit and the measurement model must not apply it again;
//   - or why it is unavailable: an enum reason and a detail text for people.
// Clock and orbit are separate questions because the model asks them at
// different instants (the clock first, at the nominal emission time, to find
// the true emission time at which it then asks the orbit).
//
// Implementations: PreciseEphemeris (SP3/CLK files), BroadcastEphemerisSource
// (broadcast navigation records), CorrectionBuffer (a stream of precise
// satellite states, the ROS node's corrections). Later: broadcast plus SSR.
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// The point of the satellite a position refers to (declared per SSR stream;
/// models/satellite_reference_point.h turns it into the offset the measurement
/// model still has to apply).
enum class EphemerisReference {
  CentreOfMass,         // the satellite antenna offset is still to be applied (SP3, broadcast, "SSRC" streams)
  AntennaPhaseCentre,   // the IONOSPHERE-FREE phase centre of the processed pair: the offset is in
                        // the orbit already (ppp_ssr_encode --reference apc)
  AntennaPhaseCentreL1, // the phase centre of the FIRST frequency (GPS/QZSS L1, Galileo E1, GLONASS G1):
                        // IGS "SSRA" streams; the model adds the PCO difference IF - L1
};

/// "centre of mass", "antenna phase centre (ionosphere-free)", "antenna phase centre (L1)".
std::string_view ephemerisReferenceName(EphemerisReference reference);

/// Why a source has no value for a satellite at an instant.
enum class EphemerisUnavailable {
  NoProducts,              // nothing loaded of the needed kind
  SatelliteNotInProducts,  // the satellite has no record at all
  OutsideSpan,             // before the first or after the last product epoch
  Gap,                     // records missing around the instant
  BadValueMarker,          // a record the interpolation needs is marked bad
  NotEnoughNodes,          // fewer records than the interpolation needs
  NoValidRecord,           // broadcast: no healthy record valid at the instant
  SystemNotModelled,       // the source cannot compute this system
};

std::string_view ephemerisUnavailableName(EphemerisUnavailable reason);

struct EphemerisClock {
  double clock_bias_s = 0.0;  // satellite clock offset, WITHOUT the relativistic (eccentricity) term
  std::optional<double> clock_drift_s_per_s;
  std::optional<double> clock_sigma_m;  // c x clock sigma, when the source gives one
};

struct EphemerisOrbit {
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();
  EphemerisReference reference = EphemerisReference::CentreOfMass;
  std::optional<double> position_sigma_m;  // when the source gives one (e.g. broadcast URA)
};

/// A value, or the reason why there is none (`detail` is for people, never parsed).
template <class T>
struct EphemerisAnswer {
  std::optional<T> value;
  EphemerisUnavailable reason = EphemerisUnavailable::NoProducts;
  std::string detail;  // empty when ok

  bool ok() const { return value.has_value(); }
  static EphemerisAnswer success(T v) { return EphemerisAnswer{std::move(v), EphemerisUnavailable::NoProducts, {}}; }
  static EphemerisAnswer unavailable(EphemerisUnavailable why, std::string detail) {
    return EphemerisAnswer{std::nullopt, why, std::move(detail)};
  }
};

class EphemerisSource {
 public:
  virtual ~EphemerisSource() = default;
  /// Satellite clock at GPST `t`.
  virtual EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const = 0;
  /// Satellite position and velocity at GPST `t`.
  virtual EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const = 0;
  /// What the source is, for run notes ("precise products", "broadcast navigation", ...).
  virtual std::string describeSource() const = 0;

 protected:
  EphemerisSource() = default;
  EphemerisSource(const EphemerisSource&) = default;
  EphemerisSource& operator=(const EphemerisSource&) = default;
  EphemerisSource(EphemerisSource&&) = default;
  EphemerisSource& operator=(EphemerisSource&&) = default;
};

}  // namespace ppp
