#pragma once
// BroadcastSsrEphemeris: broadcast ephemerides corrected with SSR, as an
// EphemerisSource. For a satellite at t: the orbit correction in force gives the
// issue of data of the broadcast record it refers to; that record's orbit is
// corrected in radial, along- and cross-track, its clock polynomial by the SSR
// clock (with the high-rate clock); the orbit refers to the point the stream
// declares (BroadcastSsrOptions::reference; satellite_reference_point.h). BeiDou
// and SBAS are not modelled. Records and corrections may be added as they arrive
// (live); a record serves only instants after its reception, so that live and
// batch choose the same record. The steps: doc/live_input.md, "Broadcast + SSR
// orbits and clocks".
// Reference: RTCM 10403.3, 3.5.12.3-3.5.12.5 (SSR orbit and clock corrections).
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/stream_problem.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

struct NavData;

struct BroadcastSsrOptions {
  /// The point the stream's orbits refer to (declared per stream; IGS SSRA
  /// streams: AntennaPhaseCentreL1, see ssrReferenceFromStreamName).
  EphemerisReference reference = EphemerisReference::AntennaPhaseCentre;
  /// Add the high-rate clock corrections (messages 1062 / 1068 / ...).
  bool use_high_rate_clock = true;
  /// Use broadcast records whose health flags say unhealthy.
  bool allow_unhealthy = false;
};

/// The SSR reference point from a stream (mount point) name: "SSRA..." -> the L1
/// antenna phase centre (AntennaPhaseCentreL1: what the IGS SSRA streams refer
/// to, satellite_reference_point.h), "SSRC..." -> centre of mass (IGS real-time
/// service naming); nullopt when the name says neither.
std::optional<EphemerisReference> ssrReferenceFromStreamName(const std::string& name);

/// A corrected state with what went into it (for ppp_ssr_check and tests).
struct SsrCorrectedState {
  BroadcastState broadcast;        // of the matching record, at t
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d correction_rac_m = Eigen::Vector3d::Zero();  // radial, along, cross at t
  double clock_s = 0.0;            // corrected, without the relativistic term
  double clock_drift_s_per_s = 0.0;
  double clock_correction_m = 0.0; // dC at t
  int iod = 0;
  double orbit_age_s = 0.0, clock_age_s = 0.0;
};

/// Whether the SSR-corrected broadcast model covers `system` (GPS, QZSS, Galileo,
/// GLONASS; BeiDou and SBAS have none here).
bool ssrBroadcastModelled(GnssSystem system);

class BroadcastSsrEphemeris : public EphemerisSource {
 public:
  BroadcastSsrEphemeris(const std::vector<NavData>& navigation, std::shared_ptr<const SsrCorrectionStore> ssr,
                        BroadcastSsrOptions options = {});
  /// No records yet (add them with addRecord); the store may still grow.
  BroadcastSsrEphemeris(std::shared_ptr<const SsrCorrectionStore> ssr, BroadcastSsrOptions options);

  /// Adds one record (unhealthy ones unless allowed, and ones failing the orbit
  /// checks, are left out: false), received at `received_at` (stream time;
  /// nullopt: serves every instant). A repeated record keeps its first reception.
  bool addRecord(const GpsLnavEphemeris& eph, std::optional<GnssTime> received_at = std::nullopt);
  bool addRecord(const GalileoEphemeris& eph, std::optional<GnssTime> received_at = std::nullopt);
  bool addRecord(const GlonassEphemeris& eph, std::optional<GnssTime> received_at = std::nullopt);
  /// (Re)checks every orbit correction of the store against the records
  /// (consistency(), satellitesWithoutBroadcast()); the navigation-file
  /// constructor does it once; after addRecord, call it again when wanted.
  void checkConsistency();
  /// Drops records whose toe / tb is more than `keep_s` before `t`; returns how many.
  std::size_t dropOlderThan(const GnssTime& t, double keep_s);
  /// The point the orbits refer to (set before the first query).
  void setReference(EphemerisReference reference) { options_.reference = reference; }
  std::size_t recordCount() const;

  /// The corrected state, or the reason (enum + detail) it is unavailable.
  EphemerisAnswer<SsrCorrectedState> correctedState(const SatelliteId& sat, const GnssTime& t) const;

  EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const override;
  EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const override;
  std::string describeSource() const override;

  /// Orbit corrections whose IOD matches no broadcast record (SsrWithoutBroadcast),
  /// with their byte offset and frame index; found when constructed.
  const StreamCounters& consistency() const { return consistency_; }
  /// Satellites with SSR orbit corrections but no broadcast record at all.
  const std::set<SatelliteId>& satellitesWithoutBroadcast() const { return satellites_without_broadcast_; }
  const BroadcastSsrOptions& options() const { return options_; }
  const SsrCorrectionStore& store() const { return *ssr_; }

 private:
  struct Record {
    std::optional<GpsLnavEphemeris> gps;
    std::optional<GalileoEphemeris> galileo;
    std::optional<GlonassEphemeris> glonass;
    GnssTime reference;  // toe / tb
    int iod = 0;
    std::optional<GnssTime> received_at;  // serves instants after it only
  };
  bool insert(Record r);
  const Record* findRecord(const SatelliteId& sat, int iod, const GnssTime& t) const;
  static BroadcastState stateOf(const Record& r, const GnssTime& t);
  static double polynomialClock_s(const Record& r, const BroadcastState& s);

  std::map<SatelliteId, std::vector<Record>> records_;
  std::shared_ptr<const SsrCorrectionStore> ssr_;
  BroadcastSsrOptions options_;
  StreamCounters consistency_;
  std::set<SatelliteId> satellites_without_broadcast_;
};

/// The GLONASS SSR IOD of a record (DF392): the index of tb in the GLONASS day,
/// in 15-min units (ICD GLONASS 5.1, 4.4: tb), 0..95.
int glonassSsrIod(const GlonassEphemeris& eph);

}  // namespace ppp
