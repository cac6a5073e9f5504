#pragma once
// Broadcast accuracy indices and their values in metres, one table each for
// the decoders (RTCM 3, UBX) and the encoders (RTCM 3):
//  - GPS / QZSS URA and BeiDou URA (one table): a 4-bit index N. Its value in
//    metres is the NOMINAL URA of IS-GPS-200 20.3.3.3.1.1: X = 2^(1 + N/2) for
//    N <= 6 (rounded there to 2.8, 5.7, 11.3 m: 2.0, 2.8, 4.0, 5.7, 8.0, 11.3,
//    16 m), X = 2^(N - 2) for 6 < N < 15 (32 ... 4096 m); N = 15 (no accuracy
//    prediction, "use at own risk") is written 8192 m. This is the value RINEX
//    navigation files carry ("SV accuracy") and RTKLIB convbin writes (its
//    ura_nominal table); BDS-SIS-ICD-B1I 5.2.4.5 defines BeiDou's URAI the same
//    way. The index of a value (the encoders) is the range it falls in
//    (IS-GPS-200 20.3.3.3.1.3: 0-2.4, 2.4-3.4, 3.4-4.85, ... 3072-6144 m),
//    so that both a nominal value and a range bound give back their index;
//  - Galileo SISA (Galileo OS SIS ICD 5.1.12, table 89): an 8-bit index,
//    0-49: 0.01 m steps from 0, 50-74: 0.02 m from 0.5 m, 75-99: 0.04 m from
//    1 m, 100-125: 0.16 m from 2 m; 126-254 spare, 255 NAPA (no accuracy
//    prediction available).
#include <optional>

namespace ppp {

/// Nominal URA [m] of a GPS/QZSS/BeiDou URA index (8192 m for 15 and any index outside 0..14).
double gpsUra_m(int index);
/// URA index (4 bits) of an accuracy in metres: the IS-GPS-200 range it falls
/// in (15 beyond 6144 m).
int gpsUraIndex(double ura_m);

/// Galileo SISA [m] of a SISA index; nullopt for NAPA (255), spare and negative indices.
std::optional<double> galileoSisa_m(int index);
/// Galileo SISA index (8 bits) of an accuracy, 255 (NAPA) for none or one beyond 6 m.
int galileoSisaIndex(const std::optional<double>& sisa_m);

}  // namespace ppp
