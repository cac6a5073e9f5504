#pragma once
// BroadcastEphemerisStore: the broadcast records of one or more navigation files,
// and the choice of the record to use for a satellite at an instant. Every
// lookup either gives a record / state or says why there is none.
//
// As an EphemerisSource it serves the measurement model with broadcast orbits
// (GPS/QZSS/Galileo/BeiDou: antenna phase centre, GLONASS: centre of mass;
// sigma = the record's URA / SISA) and clocks WITHOUT the
// relativistic eccentricity term (the model adds its own -2 r.v / c^2). The
// GPS clock refers to the L1/L2 P(Y) ionosphere-free combination; a Galileo
// I/NAV clock to E1/E5b (an E1/E5a pair would need the BGD: not applied). A
// BeiDou record's clock refers to B3I; satelliteClock() serves it for the
// B1I/B3I ionosphere-free combination (TGD1 applied, BDS-SIS-ICD-B1I 3.0
// 5.2.4.10), the BeiDou pair of the PPP signal table, while state() keeps the
// record's B3I clock. BeiDou records sit in their own list: adding them never
// changes the record chosen for a GPS, QZSS, Galileo or GLONASS satellite.
//
// Records not yet received (causal choice, the same live and in batch): a
// record decoded from a receiver or correction stream carries its reception
// time (the stream's time when it was decoded, io/transport/gnss_stream_decoder.h) and
// serves only instants AFTER it; a record of a RINEX navigation file (no
// reception time) serves every instant. So ppp_solve on a recording and the
// live input (app/live_gnss_input.h) choose the same record for the same
// data, whatever arrived later.
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

struct NavData;

/// Which Galileo message to use: the clock of an I/NAV record refers to E1/E5b,
/// that of an F/NAV record to E1/E5a (Galileo OS SIS ICD 5.1.5).
enum class GalileoPreference { INavOnly, FNavOnly, Any };

struct EphemerisSelectionOptions {
  /// Validity of a GPS/QZSS record: |t - toe| <= fit interval / 2 (IS-GPS-200
  /// 20.3.4.4: the fit interval is centred on toe; 4 h nominal).
  /// Galileo: |t - toe| <= this (Galileo records are refreshed every 10 min and
  /// nominally valid for 4 h after toe; we accept 4 h either side).
  double galileo_max_age_s = 4.0 * 3600.0;
  /// GLONASS: |t - tb| <= this. Records come every 30 min with tb mid-interval
  /// (ICD 5.1, 4.4), so 15 min suffice in a complete file; 30 min (as RTKLIB's
  /// MAXDTOE_GLO) bridges one missing record at a cost of metres.
  double glonass_max_age_s = 30.0 * 60.0;
  /// BeiDou: |t - toe| <= this. Records are uploaded hourly with toe at the hour
  /// (BDS-SIS-ICD-B1I 5.2.4: ephemeris update period 1 h); 4 h either side as
  /// for Galileo bridges gaps at metre-level cost.
  double beidou_max_age_s = 4.0 * 3600.0;
  GalileoPreference galileo = GalileoPreference::INavOnly;
  /// Use records whose health flags say unhealthy (never by default).
  bool allow_unhealthy = false;
};

/// A looked-up record: `record` is null exactly when `unavailable_reason` says why.
template <typename Record>
struct EphemerisLookup {
  const Record* record = nullptr;
  std::string unavailable_reason;
  explicit operator bool() const { return record != nullptr; }
};

/// A computed broadcast state, or the reason there is none.
struct BroadcastLookup {
  std::optional<BroadcastState> state;
  std::string unavailable_reason;
  explicit operator bool() const { return state.has_value(); }
};

class BroadcastEphemerisStore : public EphemerisSource {
 public:
  explicit BroadcastEphemerisStore(EphemerisSelectionOptions options = {}) : options_(options) {}

  /// Adds every record of a navigation file.
  void add(const NavData& nav);
  /// Adds one record. Records failing checkKeplerOrbit / checkGlonassState are
  /// refused (returns the reason); exact duplicates (same satellite, toe and
  /// issue of data) are kept once.
  std::optional<std::string> add(const GpsLnavEphemeris& eph);
  std::optional<std::string> add(const GalileoEphemeris& eph);
  std::optional<std::string> add(const GlonassEphemeris& eph);
  std::optional<std::string> add(const BeidouEphemeris& eph);
  /// The same for a record received at `received_at` (stream time; nullopt:
  /// always usable). A repeated record keeps its first reception time.
  std::optional<std::string> add(const GpsLnavEphemeris& eph, std::optional<GnssTime> received_at);
  std::optional<std::string> add(const GalileoEphemeris& eph, std::optional<GnssTime> received_at);
  std::optional<std::string> add(const GlonassEphemeris& eph, std::optional<GnssTime> received_at);
  std::optional<std::string> add(const BeidouEphemeris& eph, std::optional<GnssTime> received_at);
  /// Drops records whose reference time (toe / tb) is more than `keep_s` before
  /// `t` (bounded memory in live operation); returns how many were dropped.
  std::size_t dropOlderThan(const GnssTime& t, double keep_s);

  /// The record to use for `sat` at GPST `t`: among the healthy records whose
  /// validity interval contains t, the one with the nearest toe (ties: the later).
  EphemerisLookup<GpsLnavEphemeris> gps(const SatelliteId& sat, const GnssTime& t) const;
  EphemerisLookup<GalileoEphemeris> galileo(const SatelliteId& sat, const GnssTime& t) const;
  EphemerisLookup<GlonassEphemeris> glonass(const SatelliteId& sat, const GnssTime& t) const;
  EphemerisLookup<BeidouEphemeris> beidou(const SatelliteId& sat, const GnssTime& t) const;

  /// Position, velocity and clock of any modelled satellite (GPS, QZSS, Galileo,
  /// GLONASS, BeiDou) at GPST t, or the reason it is unavailable.
  BroadcastLookup state(const SatelliteId& sat, const GnssTime& t) const;

  /// EphemerisSource (see above).
  EphemerisAnswer<EphemerisClock> satelliteClock(const SatelliteId& sat, const GnssTime& t) const override;
  EphemerisAnswer<EphemerisOrbit> satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const override;
  std::string describeSource() const override { return "broadcast navigation records"; }

  std::size_t size() const;
  const EphemerisSelectionOptions& options() const { return options_; }

 private:
  /// Reception times of stream records, by (satellite, reference time, issue of data).
  using ReceivedKey = std::tuple<SatelliteId, GnssTime, int>;
  template <typename Record>
  bool receivedBy(const Record& r, const GnssTime& t) const;
  template <typename Record>
  void noteReceived(const Record& r, const std::optional<GnssTime>& received_at);
  /// add(eph), noting `received_at` when the record is new to `store` (its system's list).
  template <typename Record>
  std::optional<std::string> addReceived(std::map<SatelliteId, std::vector<Record>>& store, const Record& eph,
                                         const std::optional<GnssTime>& received_at);

  EphemerisSelectionOptions options_;
  std::map<ReceivedKey, GnssTime> received_;
  std::map<SatelliteId, std::vector<GpsLnavEphemeris>> gps_;
  std::map<SatelliteId, std::vector<GalileoEphemeris>> galileo_;
  std::map<SatelliteId, std::vector<GlonassEphemeris>> glonass_;
  std::map<SatelliteId, std::vector<BeidouEphemeris>> beidou_;
};

}  // namespace ppp
