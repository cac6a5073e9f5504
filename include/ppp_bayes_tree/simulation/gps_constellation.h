#pragma once
// Satellite truth for the simulator: a built-in nominal Walker-like GPS
// constellation on Keplerian orbits, or real orbits and clocks from SP3/CLK
// files, always delivered as sampled "products" (Sp3File + RinexClockFile) so
// that the simulator, the writers and the estimators all see one truth.
//
// Nominal constellation (Walker delta T/P/F, J. G. Walker 1984, "Satellite
// constellations", J. Br. Interplanet. Soc. 37): P = 6 planes, inclination
// 55 deg, semi-major axis 26 559.7 km (half a sidereal day period, IS-GPS-200
// nominal), circular by default; satellite k goes to plane k mod 6 so that
// 24..32 satellites fill the planes evenly; right ascensions 60 deg apart, mean
// anomalies 360/n apart within a plane, phased by F * 360 / T between planes.
// Positions: two-body Keplerian motion with GM of WGS 84 (IS-GPS-200
// 20.3.3.4.3), inertial -> ECEF by the rotation omega_e (t - t_ref) about z
// (Greenwich meridian aligned with the inertial x axis at t_ref).
// Velocities (ECEF) include the -omega x r term.
//
// Galileo (galileoWalkerOptions): Walker 24/3/1 at 23 222 km altitude over the
// equatorial radius (semi-major axis 29 600.137 km, period 14 h 04 min), inclination
// 56 deg, GM of the Galileo OS SIS ICD; satellites E01..E24, planes k mod 3.
// Several constellations are sampled separately and merged (mergeProducts).
//
// Satellite clocks: bias uniform in +-0.5 ms and drift uniform in +-1e-11 s/s
// per satellite (typical broadcast af0/af1 sizes), drawn from the seed.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct WalkerConstellationOptions {
  GnssSystem system = GnssSystem::GPS;  // satellites are <system><k+1>
  double gm_m3ps2 = kGmGps_m3ps2;       // of the system's ICD (its broadcast orbits)
  int satellites = 30;                  // 24..32
  int planes = 6;
  int phasing = 1;                      // Walker F
  double semi_major_axis_m = 26559.7e3;
  double eccentricity = 0.0;
  double inclination_rad = 55.0 * 3.14159265358979323846 / 180.0;
  GnssTime reference_time;              // t_ref: epoch of the elements
  double raan_offset_rad = 0.0;         // right ascension of plane 0 at t_ref
  /// Added to every mean anomaly (non-zero by default: a satellite exactly in
  /// the equator plane at a node would write z = 0.000000, the SP3 "absent" marker).
  double mean_anomaly_offset_rad = 0.1234;
};

struct KeplerianElements {
  SatelliteId satellite;
  double semi_major_axis_m = 0.0;
  double eccentricity = 0.0;
  double inclination_rad = 0.0;
  double raan_rad = 0.0;               // inertial, at t_ref
  double argument_of_perigee_rad = 0.0;
  double mean_anomaly_rad = 0.0;        // at t_ref
};

/// The nominal Galileo constellation: Walker 24/3/1, 23 222 km altitude, 56 deg.
WalkerConstellationOptions galileoWalkerOptions();
/// Galileo nominal altitude over the equatorial radius [m] (ESA).
constexpr double kGalileoAltitude_m = 23222.0e3;

class WalkerConstellation {
 public:
  explicit WalkerConstellation(WalkerConstellationOptions options = {});
  const std::vector<KeplerianElements>& satellites() const { return elements_; }
  const WalkerConstellationOptions& options() const { return options_; }
  /// Orbital period 2 pi sqrt(a^3 / GM) [s].
  double period_s() const;
  /// ECEF position and velocity of satellite i at t.
  void state(std::size_t i, const GnssTime& t, Eigen::Vector3d& position_ecef_m,
             Eigen::Vector3d& velocity_ecef_mps) const;

 private:
  WalkerConstellationOptions options_;
  std::vector<KeplerianElements> elements_;
};

/// Sampled truth products of a span: SP3 (positions and clocks, every
/// `orbit_interval_s`) and RINEX clock records (every `clock_interval_s`).
struct TruthProducts {
  Sp3File orbits;
  RinexClockFile clocks;
};

struct ProductSampling {
  GnssTime first, last;          // span of the samples (inclusive)
  double orbit_interval_s = 300.0;
  double clock_interval_s = 30.0;
};

/// Samples the nominal constellation; clock biases/drifts drawn from `clock_seed`.
TruthProducts sampleWalkerProducts(const WalkerConstellation& constellation, const ProductSampling& sampling,
                                   std::uint64_t clock_seed);

/// Adds the satellites of `other` (same sampling epochs) to `into`; the clock
/// header's system becomes 'M' when the systems differ.
void mergeProducts(TruthProducts& into, const TruthProducts& other);

/// The GPS part of real products, restricted to [first, last] (records outside dropped).
TruthProducts restrictProducts(const Sp3File& sp3, const RinexClockFile& clk, const GnssTime& first,
                               const GnssTime& last);

}  // namespace ppp
