#pragma once
// BeiDou D1/D2 broadcast ephemeris (BDS-SIS-ICD-B1I 3.0, section 5.2.4; RINEX 3.05
// table A14; RTCM 10403.3 message 1042). The orbit has the GPS quasi-Keplerian
// layout; times are kept as GPST instants (BDT = GPST - 14 s), the week and
// seconds of week as broadcast in BDT.
#include <optional>

#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

struct BeidouEphemeris {
  SatelliteId satellite;
  ClockPolynomial clock;  // toc as GPST
  KeplerOrbit orbit;      // toe as GPST, toe_sow as BDT seconds of week
  int aode = 0;           // age of data, ephemeris
  int aodc = 0;           // age of data, clock
  int bdt_week = 0;       // continuous BDT week (0 = 2006-01-01)
  int health = 0;         // SatH1 (0 = healthy)
  double ura_m = 2.0;     // user range accuracy (RINEX: metres; broadcast as URAI, see beidouUra_m)
  double tgd1_s = 0.0;    // B1I group delay (relative to B3I)
  double tgd2_s = 0.0;    // B2I group delay (relative to B3I)
  std::optional<double> transmission_sow;  // BDT seconds of week; nullopt when the source has none (RTCM 1042)

  /// GEO satellites use the rotated user algorithm (ICD 5.2.4.12); see isBeidouGeo.
  bool isGeo() const;
};

/// BeiDou GEO satellites: PRN 1-5 and 59-63 (BDS-SIS-ICD-B1I 3.0, 5.2.4.12 and
/// 5.3: GEO satellites broadcast D2, the others D1).
constexpr bool isBeidouGeo(int prn) { return prn <= 5 || prn >= 59; }
inline bool BeidouEphemeris::isGeo() const { return isBeidouGeo(satellite.prn); }

// BDT: kGpstMinusBdt_s, kBdtWeekZeroGpsWeek (types/time_system.h), fromBdtWeek,
// toBdtWeek (types/gnss_time.h).

/// URA [m] of a URA index N (BDS-SIS-ICD-B1I 3.0, 5.2.4.5, the GPS definition of
/// IS-GPS-200 20.3.3.3.1.1): the one table of types/broadcast_accuracy.h (nominal
/// 2.0, 2.8, 4.0, 5.7, 8.0, 11.3, 16, 32 ... 4096 m; N = 15 gives 8192 m, as RINEX writers do).
double beidouUra_m(int index);
/// The URA index of `ura_m` (the range it falls in; inverse of beidouUra_m).
int beidouUraIndex(double ura_m);

}  // namespace ppp
