#pragma once
// CorrectionBuffer: precise satellite states that arrive as a stream of
// batches (one batch = all satellites at one product epoch: the decoded form
// of a real-time correction stream, SSR applied to broadcast, or a real-time
// SP3/CLK feed; the ROS message ppp_bayes_tree/PreciseCorrections), served as
// a PreciseEphemeris so that the single measurement model uses them unchanged.
//
// Interpolation between consecutive batches follows the PreciseEphemeris rules
// (precise_ephemeris.h): orbits by a cubic Hermite polynomial between the two
// bracketing batches when both carry a velocity (else the Lagrange window of
// `interpolation.interpolation_points` batches), clocks linearly between the
// two bracketing records; nothing is extrapolated: a time after the newest
// batch, a satellite missing from a bracketing batch, or batches too far apart
// give the explicit reason. Batches older than `history_s` before the newest
// are dropped. A batch at an epoch already held is ignored (the first is kept);
// a batch older than the newest but inside the history is inserted in order.
// The buffer is an EphemerisSource (the ROS node's): the same answers as its
// ephemeris(), with the orbit reference point of `options.reference`.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// One satellite of a correction batch (absent values: nullopt, never 0).
struct SatelliteCorrection {
  SatelliteId satellite;
  std::optional<Eigen::Vector3d> position_ecef_m;    // centre of mass, IGS frame of the product
  std::optional<Eigen::Vector3d> velocity_ecef_mps;
  std::optional<double> clock_bias_s;                // satellite clock offset (product convention)
  std::optional<double> clock_drift_s_per_s;
  std::optional<double> position_sigma_m, velocity_sigma_mps, clock_sigma_s, clock_drift_sigma_s_per_s;
};

/// All satellites at one product epoch.
struct CorrectionBatch {
  GnssTime time;  // GPST
  std::vector<SatelliteCorrection> satellites;
  std::string orbit_source;     // e.g. "IGS0OPSFIN SP3 (15 min, interpolated)"
  std::string clock_source;     // e.g. "IGS0OPSFIN CLK 30 s"
  std::string reference_frame;  // e.g. "IGS20"
  std::string bias_set;         // code-bias set consistent with the clocks, e.g. "COD0OPSFIN OSB"
};

struct CorrectionBufferOptions {
  /// Interpolation rules. Defaults for streams: Hermite between batches,
  /// clock spacing limit 1.5 x the most common batch spacing.
  PreciseEphemerisOptions interpolation = streamInterpolation();
  /// Batches older than the newest minus this are dropped [s] (> 0; infinity:
  /// every batch is kept, as ppp_bag_solve does for a whole bag).
  double history_s = 900.0;
  /// The point the batch positions refer to (the PreciseCorrections message: centre of mass).
  EphemerisReference reference = EphemerisReference::CentreOfMass;

  static PreciseEphemerisOptions streamInterpolation() {
    PreciseEphemerisOptions o;
    o.hermite_between_velocity_nodes = true;
    o.interpolation_points = 4;  // Lagrange fallback when velocities are missing
    return o;
  }
};

enum class BatchAddResult { Added, Duplicate, TooOld, InvalidTime };

class CorrectionBuffer : public EphemerisSource {
 public:
  explicit CorrectionBuffer(CorrectionBufferOptions options = {});
  CorrectionBuffer(const CorrectionBuffer&) = delete;
  CorrectionBuffer& operator=(const CorrectionBuffer&) = delete;

  /// Adds a batch; the ephemeris is rebuilt (the reference stays valid).
  BatchAddResult add(CorrectionBatch batch);
  /// The products of the batches held (same object for the buffer's lifetime).
  const PreciseEphemeris& ephemeris() const { return ephemeris_; }
  /// EphemerisSource: ephemeris()'s answers (with its edge extension).
  EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const override {
    return ephemeris_.satelliteClock(sat, t);
  }
  EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const override {
    auto a = ephemeris_.satelliteOrbit(sat, t);
    if (a.value) a.value->reference = options_.reference;
    return a;
  }
  std::string describeSource() const override { return "correction stream (precise satellite states)"; }
  std::optional<GnssTime> newest() const;
  std::optional<GnssTime> oldest() const;
  /// True when a batch strictly after `t` is held: interpolation is then
  /// possible at t and over the signal travel time before it even at the first
  /// batch of a stream (a node therefore waits up to one batch interval).
  bool covers(const GnssTime& t) const { return !batches_.empty() && batches_.back().time > t; }
  std::size_t size() const { return batches_.size(); }
  /// The newest batch (nullptr when empty).
  const CorrectionBatch* latest() const { return batches_.empty() ? nullptr : &batches_.back(); }
  void clear();
  const CorrectionBufferOptions& options() const { return options_; }

 private:
  void rebuild();
  CorrectionBufferOptions options_;
  std::vector<CorrectionBatch> batches_;  // time order
  PreciseEphemeris ephemeris_;
};

}  // namespace ppp
