#pragma once
// UBX RXM-SFRBX encoder for broadcast records: turns a GLONASS or BeiDou record
// into the navigation words a u-blox receiver would deliver (strings with their
// Hamming code, subframes / pages with their BCH parity), so that a decoder
// (ours, RTKLIB's convbin) can be fed real broadcast values when no recording
// carries them. The bit layouts are those the decoder reads
// (src/core/io/ubx/ubx_nav_layout.h: GLONASS ICD 5.1 table 4.5; BDS-SIS-ICD-B1I
// 5.2 / 5.3). Values are rounded to the broadcast resolution; a value that does
// not fit its field throws std::invalid_argument naming it. Fields the records
// do not carry (P1-P4, ln, F_T, N_T, M, ionosphere, almanac) are written 0
// (GLONASS M: 1, a GLONASS-M satellite).
//
// Each function returns complete UBX frames (sync, class 0x02, id 0x13,
// checksum). For tests and replay, not used by the decoders.
#include <cstdint>
#include <vector>

#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

using UbxFrameBytes = std::vector<std::uint8_t>;

/// GLONASS strings 1-5 of one frame (sigId 0, L1OF; freqId = channel + 7):
/// tb and tk from the record (tk from the message frame time, to 30 s), the
/// frame id in word 4's upper half.
std::vector<UbxFrameBytes> encodeGlonassSfrbx(const GlonassEphemeris& eph, std::uint16_t frame_id);

/// BeiDou D1 subframes 1-3 (MEO/IGSO; SOW sow, sow + 6, sow + 12) or, for a GEO
/// record, D2 subframe 1 pages 1-10 (SOW sow + 3 (page - 1)); sigId 0 (B1I D1) or
/// 1 (B1I D2). `sow` is the BDT second of week of the first part.
std::vector<UbxFrameBytes> encodeBeidouSfrbx(const BeidouEphemeris& eph, std::uint32_t sow);

/// An RXM-RAWX without measurements at GPST `t`: gives a decoder its time.
UbxFrameBytes encodeRawxTime(const GnssTime& t);

}  // namespace ppp
