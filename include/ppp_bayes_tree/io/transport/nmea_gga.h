#pragma once
// NMEA 0183 GGA sentence (Global Positioning System Fix Data), as NTRIP
// network casters (VRS, nearest-base mountpoints) expect from their clients:
//
//   $GPGGA,hhmmss.ss,ddmm.mmmmm,N,dddmm.mmmmm,E,1,12,1.0,hhh.hhh,M,0.000,M,,*CS
//
// The checksum CS is the XOR of the characters between '$' and '*', written as
// two upper-case hex digits (NMEA 0183 v4.11, section 5.3.1). The height is
// given as altitude above the geoid with geoid separation 0 (so the field is
// the ellipsoidal height), which is what casters use to pick a base.
#include <cstdint>
#include <string>
#include <string_view>

namespace ppp {

/// XOR checksum of the characters between '$' and '*' (or the whole text
/// when it holds no '$').
std::uint8_t nmeaChecksum(std::string_view sentence);

/// A complete GGA sentence with checksum and "\r\n"; `utc_seconds_of_day` in [0, 86400).
std::string makeNmeaGga(double latitude_deg, double longitude_deg, double height_m,
                        double utc_seconds_of_day);

}  // namespace ppp
