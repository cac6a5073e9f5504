#pragma once
// RTCM 3 broadcast ephemeris encoder (RTCM 10403.3 3.5.10-3.5.14), the inverse
// of Rtcm3Decoder's ephemeris part, field for field in the decoder's layout:
//  - 1019 GPS LNAV and 1044 QZSS LNAV (GpsLnavEphemeris, by the satellite's system);
//  - 1020 GLONASS (GlonassEphemeris);
//  - 1045 Galileo F/NAV and 1046 Galileo I/NAV (GalileoEphemeris, by its type);
//  - 1042 BeiDou D1/D2 (BeidouEphemeris; BDS-SIS-ICD-B1I 5.2.4 scale factors);
// so that a processed day's navigation file can be sent as a caster would
// (ppp_stream_make). Scale factors are those of the ICDs (IS-GPS-200 table
// 20-III, Galileo OS SIS ICD table 60, GLONASS ICD 5.1 table 4.5).
//
// Values are rounded to the field's resolution. What a message cannot carry
// comes back different after decoding, by design:
//  - GPS URA: the 4-bit index (IS-GPS-200 20.3.3.3.1.3) of the smallest table value
//    not below the accuracy (RINEX 2.0 m -> index 0 -> 2.4 m; types/broadcast_accuracy.h);
//  - GPS fit interval: only "4 h" or "more than 4 h" (decoded as 6 h);
//  - Galileo data sources: fixed by the message (1045: 258, 1046: 517);
//  - GLONASS tk: 30-s steps; tb: 15-min steps (both Moscow time of day);
//  - the RINEX transmission time (not a field of any of these messages).
// A value outside its field throws std::out_of_range (BitWriter), a satellite
// the message has no number for std::invalid_argument.
#include <cstdint>
#include <vector>

#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/broadcast_accuracy.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

/// 1019 (GPS) or 1044 (QZSS) payload, without framing.
std::vector<std::uint8_t> encodeEphemerisPayload(const GpsLnavEphemeris& eph);
/// 1020 payload.
std::vector<std::uint8_t> encodeEphemerisPayload(const GlonassEphemeris& eph);
/// 1045 (F/NAV) or 1046 (I/NAV) payload.
std::vector<std::uint8_t> encodeEphemerisPayload(const GalileoEphemeris& eph);
/// 1042 payload.
std::vector<std::uint8_t> encodeEphemerisPayload(const BeidouEphemeris& eph);

/// The RTCM message type the record is sent as (1019, 1020, 1042, 1044, 1045, 1046).
int ephemerisMessageType(const GpsLnavEphemeris& eph);
int ephemerisMessageType(const GlonassEphemeris& eph);
int ephemerisMessageType(const GalileoEphemeris& eph);
int ephemerisMessageType(const BeidouEphemeris& eph);

}  // namespace ppp
