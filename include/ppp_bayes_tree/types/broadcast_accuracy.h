#pragma once
// Broadcast accuracy indices and their values in metres, one table each for
// the decoders (RTCM 3, UBX) and the encoders (RTCM 3):
//  - GPS / QZSS URA (IS-GPS-200 20.3.3.3.1.3): a 4-bit index N whose value is
//    the upper bound of its accuracy range (2.4, 3.4, 4.85, ... 6144 m);
//    N = 15 (no accuracy prediction) is kept as the largest bound, 6144 m;
//  - Galileo SISA (Galileo OS SIS ICD 5.1.12, table 89): an 8-bit index,
//    0-49: 0.01 m steps from 0, 50-74: 0.02 m from 0.5 m, 75-99: 0.04 m from
//    1 m, 100-125: 0.16 m from 2 m; 126-254 spare, 255 NAPA (no accuracy
//    prediction available).
// (BeiDou's URA index is in types/beidou_ephemeris.h.)
#include <optional>

namespace ppp {

/// GPS URA [m] of a URA index (6144 m for 15 and any index outside 0..14).
double gpsUra_m(int index);
/// GPS URA index (4 bits) of an accuracy in metres: the smallest index whose
/// value is not below it (15 beyond the table).
int gpsUraIndex(double ura_m);

/// Galileo SISA [m] of a SISA index; nullopt for NAPA (255), spare and negative indices.
std::optional<double> galileoSisa_m(int index);
/// Galileo SISA index (8 bits) of an accuracy, 255 (NAPA) for none or one beyond 6 m.
int galileoSisaIndex(const std::optional<double>& sisa_m);

}  // namespace ppp
