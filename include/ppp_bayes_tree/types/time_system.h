#pragma once
// GNSS time systems and the UTC leap-second table.
//
// All instants inside the project are GPS time (see gnss_time.h); a time system
// only matters where calendar dates are read or written (RINEX headers, UTC output).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

enum class TimeSystem : std::uint8_t {
  GPS,      // GPST: continuous, = TAI - 19 s
  Galileo,  // GST: steered to GPST (offset below 50 ns, ignored here)
  BeiDou,   // BDT: = GPST - 14 s (IS BDS-SIS ICD 3.0, sec. 5.1.2)
  QZSS,     // QZSST: aligned with GPST
  UTC,      // UTC: GPST - (TAI-UTC - 19 s)
  GLONASS,  // GLONASST: UTC(SU) + 3 h
  TAI,
};

/// BDT = GPST - 14 s (BDS-SIS-ICD-B1I 3.0, 5.1.2: BDT started 2006-01-01 00:00:00
/// UTC, when GPST - UTC was 14 s); BDT week 0 is GPS week 1356.
constexpr double kGpstMinusBdt_s = 14.0;
constexpr int kBdtWeekZeroGpsWeek = 1356;
/// GLONASS time = UTC(SU) + 3 h (GLONASS ICD edition 5.1, 3.3.3).
constexpr double kGlonassMinusUtc_s = 3.0 * 3600.0;

/// GPST minus a system's time of week [s], for the systems whose time counts weeks
/// in step with GPST: BeiDou 14 s (BDT), GPS, Galileo (GST), QZSS, SBAS and NavIC 0.
/// nullopt for GLONASS, whose time is UTC(SU) + 3 h with leap seconds (a time of
/// day, placed by each reader with GnssTime::offsetToSystem_s).
std::optional<double> gpstMinusWeekTime_s(GnssSystem system);

/// Three-letter RINEX code ("GPS", "GAL", "BDT", "QZS", "UTC", "GLO", "TAI").
std::string_view timeSystemCode(TimeSystem system);
/// Parses a RINEX time-system code; nullopt when unknown.
std::optional<TimeSystem> parseTimeSystem(std::string_view code);

/// Leap seconds: TAI - UTC in whole seconds at the UTC instant given as seconds
/// since 1972-01-01 00:00:00 UTC ignoring leap seconds (i.e. a POSIX-like count).
/// Table source: IERS Bulletin C 71 (January 2026: no leap second at the end of
/// June 2026). The last entry is 2017-01-01 (TAI-UTC = 37 s).
int taiMinusUtcAtUtcDay(std::int64_t days_since_1972);

/// Days (since 1972-01-01) on which the leap-second table stops being known to be
/// complete; dates after it use the last value (there is no announced change).
std::int64_t leapTableValidUntilDay();

}  // namespace ppp
