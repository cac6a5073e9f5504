#pragma once
// GnssTime: an instant in GPS time, held as whole seconds since the GPS epoch
// (1980-01-06 00:00:00 GPST) plus a fraction in [0, 1) s, so that epoch
// arithmetic keeps sub-nanosecond resolution over decades.
#include <cstdint>
#include <string>

#include "ppp_bayes_tree/types/time_system.h"

namespace ppp {

/// Broken-down calendar date and time in some time system.
struct CalendarTime {
  int year = 1980;
  int month = 1;   // 1..12
  int day = 1;     // 1..31
  int hour = 0;    // 0..23
  int minute = 0;  // 0..59
  double second = 0.0;  // [0, 61) (a UTC leap second reads 60.x)
};

/// GPS week number (continuous, no roll-over) and seconds of week.
struct GpsWeekTime {
  int week = 0;
  double seconds_of_week = 0.0;
};

class GnssTime {
 public:
  GnssTime() = default;
  /// From whole and fractional seconds since the GPS epoch; normalises so that
  /// 0 <= fraction < 1.
  static GnssTime fromGpsSeconds(std::int64_t whole_s, double fraction_s = 0.0);
  /// From GPS week and seconds of week (GPST).
  static GnssTime fromGpsWeek(int week, double seconds_of_week);
  /// From a calendar date and time read in the given time system.
  /// Throws std::invalid_argument on a date that does not exist.
  static GnssTime fromCalendar(const CalendarTime& calendar, TimeSystem system = TimeSystem::GPS);
  /// From a Modified Julian Date in the given time system.
  static GnssTime fromMjd(std::int64_t mjd_day, double fraction_of_day,
                          TimeSystem system = TimeSystem::GPS);

  std::int64_t wholeSeconds() const { return whole_s_; }
  double fraction() const { return fraction_s_; }
  /// Seconds since the GPS epoch as a double (loses precision: ~1e-7 s today).
  double toGpsSecondsDouble() const { return static_cast<double>(whole_s_) + fraction_s_; }

  GpsWeekTime gpsWeek() const;
  CalendarTime toCalendar(TimeSystem system = TimeSystem::GPS) const;
  /// Modified Julian Date in the given time system (integer day plus fraction).
  double mjd(TimeSystem system = TimeSystem::GPS) const;
  /// Day of year (1..366) in the given time system.
  int dayOfYear(TimeSystem system = TimeSystem::GPS) const;
  /// Seconds to add to a GPST reading to get the reading in `system`
  /// (e.g. -18 for UTC in 2026, -14 for BDT, +3 h - 18 s for GLONASS).
  double offsetToSystem_s(TimeSystem system) const;

  /// Text "2026-05-13 00:00:00.0000000 GPS" (time-system code last).
  std::string toString(TimeSystem system = TimeSystem::GPS, int decimals = 7) const;

  GnssTime& operator+=(double dt_s);
  GnssTime& operator-=(double dt_s) { return *this += -dt_s; }
  friend GnssTime operator+(GnssTime t, double dt_s) { return t += dt_s; }
  friend GnssTime operator-(GnssTime t, double dt_s) { return t -= dt_s; }
  /// Difference a - b in seconds (exact for the whole part).
  friend double operator-(const GnssTime& a, const GnssTime& b) {
    return static_cast<double>(a.whole_s_ - b.whole_s_) + (a.fraction_s_ - b.fraction_s_);
  }
  friend bool operator<(const GnssTime& a, const GnssTime& b) {
    return a.whole_s_ < b.whole_s_ || (a.whole_s_ == b.whole_s_ && a.fraction_s_ < b.fraction_s_);
  }
  friend bool operator>(const GnssTime& a, const GnssTime& b) { return b < a; }
  friend bool operator<=(const GnssTime& a, const GnssTime& b) { return !(b < a); }
  friend bool operator>=(const GnssTime& a, const GnssTime& b) { return !(a < b); }
  friend bool operator==(const GnssTime& a, const GnssTime& b) {
    return a.whole_s_ == b.whole_s_ && a.fraction_s_ == b.fraction_s_;
  }
  friend bool operator!=(const GnssTime& a, const GnssTime& b) { return !(a == b); }

 private:
  std::int64_t whole_s_ = 0;
  double fraction_s_ = 0.0;  // [0, 1)
};

/// The GPST instant of BDT week `bdt_week` (continuous, 0 = 2006-01-01), second `bdt_sow`.
GnssTime fromBdtWeek(int bdt_week, double bdt_sow);
/// BDT week (continuous) and BDT seconds of week of the GPST instant `t` (inverse of fromBdtWeek).
GpsWeekTime toBdtWeek(const GnssTime& t);
/// GLONASS time of day [s] (Moscow day, UTC(SU) + 3 h) of the GPST instant `t`.
double glonassSecondsOfDay(const GnssTime& t);
/// GLONASS time of day [s] of a UTC reading given as seconds of the UTC day or
/// week (any multiple of the day, either sign).
double glonassSecondsOfDayFromUtc(double utc_s);

/// `t` moved by whole weeks to within half a week of `near`: broadcast times
/// given as seconds of week lie in the week whose instant is nearest to a
/// known time (IS-GPS-200 20.3.3.4.3: a difference beyond +-302400 s crosses a
/// week). Exactly half a week stays.
GnssTime withinHalfWeek(const GnssTime& near, GnssTime t);
/// The instant with GPS seconds of week `sow` nearest to `near`.
GnssTime nearestSecondsOfWeek(const GnssTime& near, double sow);

/// Days from 1970-01-01 for a proleptic Gregorian date (negative before 1970).
std::int64_t daysFromCivil(int year, int month, int day);
/// True when (year, month, day) is a valid Gregorian date.
bool isValidDate(int year, int month, int day);

}  // namespace ppp
