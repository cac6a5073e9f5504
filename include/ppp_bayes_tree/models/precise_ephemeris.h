#pragma once
// PreciseEphemeris: satellite positions, velocities and clocks from precise
// products (SP3 orbits, RINEX clock files), for any time inside their span.
// Orbit: Lagrange interpolation over a window of consecutive SP3 nodes (10,
// degree 9) in a non-rotating frame aligned with ECEF at the query time; clock:
// linear interpolation between the two bracketing records, from the clock files
// when any is loaded, else from the SP3 (never mixed). Nothing is extrapolated:
// a query returns a value or the reason why there is none; only as an
// EphemerisSource is the span extended by kMaxEdgeExtension_s at its edges.
// Positions refer to the centre of mass. Details: doc/measurement_model.md,
// "Precise orbits and clocks".
#include <array>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

enum class ProductStatus {
  Ok,
  NoProducts,              // nothing loaded of the needed kind
  SatelliteNotInProducts,  // the satellite has no record at all
  OutsideSpan,             // time before the first or after the last product epoch
  Gap,                     // nodes missing around the time (spacing above the maximum)
  BadValueMarker,          // a node the window needs carries the SP3 bad-value marker
  NotEnoughNodes,          // fewer nodes than the interpolation order needs
};

std::string_view productStatusName(ProductStatus status);
/// The EphemerisSource reason of a product status (not Ok).
EphemerisUnavailable ephemerisUnavailable(ProductStatus status);

/// A value, or the reason why it is unavailable.
template <class T>
struct ProductResult {
  std::optional<T> value;
  ProductStatus status = ProductStatus::NoProducts;
  std::string reason;  // empty when ok

  bool ok() const { return value.has_value(); }
  static ProductResult success(T v) { return ProductResult{std::move(v), ProductStatus::Ok, {}}; }
  static ProductResult failure(ProductStatus s, std::string why) {
    return ProductResult{std::nullopt, s, std::move(why)};
  }
};

enum class VelocitySource { PositionInterpolant, Sp3VelocityRecords };
enum class ClockSource { RinexClock, Sp3 };

struct SatelliteOrbit {
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();
  VelocitySource velocity_source = VelocitySource::PositionInterpolant;
  GnssTime window_first, window_last;  // first and last node used
  int nodes_used = 0;
};

struct SatelliteClock {
  double clock_bias_s = 0.0;
  /// Slope between the two records used (nullopt when the time hit a record
  /// that has no usable neighbour).
  std::optional<double> clock_drift_s_per_s;
  ClockSource source = ClockSource::RinexClock;
  bool exact_record = false;  // the time coincides with a record
};

struct PreciseEphemerisOptions {
  /// Number of nodes of the Lagrange window (degree + 1), at least 2.
  int interpolation_points = 10;
  /// Largest spacing between consecutive nodes inside a window; <= 0 means 1.5 x
  /// the smallest SP3 epoch interval loaded.
  double max_node_spacing_s = 0.0;
  /// When a centred window would straddle a gap or a bad-value marker: false
  /// (default) refuses the query with the reason; true shifts the window to the
  /// side of the gap that holds the time (as at the edges of the data).
  bool shift_window_at_gaps = false;
  /// Interpolate in the non-rotating frame aligned with ECEF at the query time.
  bool interpolate_in_inertial_frame = true;
  /// Use SP3 V records for the velocity when the whole window has them.
  bool use_sp3_velocity = true;
  /// Largest spacing between the two clock records bracketing the time; <= 0
  /// means 1.5 x the most common spacing of the clock source.
  double max_clock_spacing_s = 0.0;
  /// Streams of satellite states (correction messages, CorrectionBuffer): when
  /// both nodes bracketing the time carry a velocity, interpolate the orbit by a
  /// cubic Hermite polynomial between those two nodes only (in the same
  /// inertial-like frame), instead of the Lagrange window. Same availability
  /// rules (span, gap, marker); needs no node beyond the bracketing pair, so a
  /// real-time stream is usable as soon as a node at or after the time exists.
  /// Error bound |d4x/dt4| h^4 / 384: ~0.1 mm for GPS at h = 30 s.
  bool hermite_between_velocity_nodes = false;
  /// load(): find and mark single bad orbit and clock values (product_sanity.h).
  /// Off only to measure what the estimators catch on their own (test/integrity).
  bool check_products = true;
};

struct ProductSpan {
  GnssTime first, last;
};

class PreciseEphemeris : public EphemerisSource {
 public:
  explicit PreciseEphemeris(PreciseEphemerisOptions options = {});
  PreciseEphemeris(const PreciseEphemeris&) = default;
  PreciseEphemeris& operator=(const PreciseEphemeris&) = default;
  PreciseEphemeris(PreciseEphemeris&&) = default;
  PreciseEphemeris& operator=(PreciseEphemeris&&) = default;

  /// Adds one SP3 file; files of consecutive days merge, and an epoch present in
  /// both (the shared midnight) is kept once (the first valid one).
  void addOrbits(const Sp3File& file);
  /// Adds one RINEX clock file (AS records); overlapping epochs are kept once.
  void addClocks(const RinexClockFile& file);

  /// Reads and merges the given files (throws ParseError / FileOpenError).
  static PreciseEphemeris load(const std::vector<std::string>& sp3_paths,
                               const std::vector<std::string>& clock_paths,
                               PreciseEphemerisOptions options = {});
  /// Same, keeping only what serves `filter` (systems; the time window of the
  /// observations): SP3 epochs within interpolation_points + 2 node intervals of
  /// the window (reading stops after it), clock records within
  /// kClockWindowMargin_s. Every query inside the window then gives what the
  /// unfiltered load gives.
  static PreciseEphemeris load(const std::vector<std::string>& sp3_paths,
                               const std::vector<std::string>& clock_paths, const RecordFilter& filter,
                               PreciseEphemerisOptions options = {});
  static constexpr double kClockWindowMargin_s = 7200.0;

  ProductResult<SatelliteOrbit> orbit(const SatelliteId& sat, const GnssTime& t) const;

  /// Scratch for many orbit() queries at one time (all satellites at a simulated
  /// epoch): the Lagrange weights and Earth-rotation terms of the last interpolation
  /// window, used again when the next window has the same node times and query time
  /// (the satellites of one product share their epochs) instead of being computed per
  /// satellite. The results are the same numbers either way.
  class OrbitQueryScratch {
    friend class PreciseEphemeris;
    static constexpr std::size_t kCapacity = 30;  // the largest interpolation window
    GnssTime t_;
    double h_ = 0.0;
    std::size_t size_ = 0;  // 0: nothing cached
    std::array<GnssTime, kCapacity> node_times_;
    std::array<double, kCapacity> w_, dw_, cos_, sin_;
  };
  /// orbit(sat, t), sharing the window terms through `scratch` (see above).
  ProductResult<SatelliteOrbit> orbit(const SatelliteId& sat, const GnssTime& t, OrbitQueryScratch& scratch) const;
  ProductResult<SatelliteClock> clock(const SatelliteId& sat, const GnssTime& t) const;

  /// EphemerisSource: clock() and orbit() plus the edge extension (see above).
  EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const override;
  EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const override;
  std::string describeSource() const override { return "precise products (SP3/CLK)"; }
  /// Largest distance outside the product span over which the edge is extended.
  static constexpr double kMaxEdgeExtension_s = 0.2;

  std::optional<ProductSpan> orbitSpan() const;
  /// Span of the clock source in use (CLK when loaded, else SP3).
  std::optional<ProductSpan> clockSpan() const;
  std::set<SatelliteId> orbitSatellites() const;
  std::set<SatelliteId> clockSatellites() const;
  ClockSource clockSource() const { return clocks_.empty() ? ClockSource::Sp3 : ClockSource::RinexClock; }
  /// Smallest SP3 epoch interval loaded (0 when none).
  double orbitInterval_s() const { return orbit_interval_s_; }
  double maxNodeSpacing_s() const;
  double maxClockSpacing_s() const;
  const PreciseEphemerisOptions& options() const { return options_; }
  /// Merge notes: de-duplicated overlap epochs, conflicting duplicates.
  const ParseReport& mergeReport() const { return merge_report_; }

 private:
  struct OrbitNode {
    GnssTime time;
    std::optional<Eigen::Vector3d> position_ecef_m;  // nullopt: bad-value marker
    std::optional<Eigen::Vector3d> velocity_ecef_mps;
  };
  struct ClockNode {
    GnssTime time;
    std::optional<double> clock_bias_s;  // nullopt: absent or bad-value marker
    bool marked_bad = false;
  };

  ProductResult<SatelliteClock> interpolateClock(const std::vector<ClockNode>& series, const SatelliteId& sat,
                                                 const GnssTime& t, ClockSource source) const;
  std::optional<ProductSpan> spanOfClockSource() const;
  template <class Node>
  static std::optional<SatelliteOrbit> hermite(const Node& l, const Node& r, const GnssTime& t, bool inertial);

  PreciseEphemerisOptions options_;
  std::map<SatelliteId, std::vector<OrbitNode>> orbits_;
  std::map<SatelliteId, std::vector<ClockNode>> clocks_;      // from RINEX clock files
  std::map<SatelliteId, std::vector<ClockNode>> sp3_clocks_;  // from the SP3 P records
  std::optional<ProductSpan> orbit_span_;
  std::optional<ProductSpan> clock_span_;
  double orbit_interval_s_ = 0.0;
  double clock_interval_s_ = 0.0;  // most common CLK spacing
  ParseReport merge_report_{"precise products"};
};

/// Coverage of a time range by the loaded products, for ppp_inspect.
struct ProductCoverage {
  GnssTime first, last;
  std::optional<ProductSpan> orbit_span, clock_span;
  bool orbit_span_covers = false;
  bool clock_span_covers = false;
  std::set<SatelliteId> missing_orbit;  // needed satellites without any orbit
  std::set<SatelliteId> missing_clock;  // needed satellites without any clock
  /// Needed satellites present but unavailable at some checked epochs: the
  /// number of such epochs and the first reason.
  std::map<SatelliteId, std::pair<std::size_t, std::string>> orbit_gaps, clock_gaps;
  std::size_t epochs_checked = 0;

  bool complete() const {
    return orbit_span_covers && clock_span_covers && missing_orbit.empty() && missing_clock.empty() &&
           orbit_gaps.empty() && clock_gaps.empty();
  }
  /// Human-readable lines.
  std::vector<std::string> describe() const;
};

/// Checks orbit and clock availability for every needed satellite at first,
/// first + interval, ..., last (at most 100000 epochs are checked).
ProductCoverage checkCoverage(const PreciseEphemeris& products, const GnssTime& first, const GnssTime& last,
                              double interval_s, const std::set<SatelliteId>& needed);

}  // namespace ppp
