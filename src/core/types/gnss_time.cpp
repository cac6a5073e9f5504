#include "ppp_bayes_tree/types/gnss_time.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ppp {
namespace {

constexpr std::int64_t kSecondsPerDay = 86400;
constexpr std::int64_t kSecondsPerWeek = 604800;
constexpr std::int64_t kGpsEpochMjd = 44244;  // 1980-01-06
constexpr int kGpsMinusTaiS = -19;            // GPST = TAI - 19 s

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  std::int64_t q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

/// Split a real number of seconds into whole + [0,1) fraction.
void splitSeconds(double s, std::int64_t& whole, double& fraction) {
  const double f = std::floor(s);
  whole = static_cast<std::int64_t>(f);
  fraction = s - f;
  if (fraction >= 1.0) {  // guards against rounding of s - floor(s)
    whole += 1;
    fraction -= 1.0;
  }
}

const std::int64_t kGpsEpochDays = daysFromCivil(1980, 1, 6);  // days since 1970
const std::int64_t kDay1972 = daysFromCivil(1972, 1, 1);

/// TAI-UTC for a UTC reading expressed in whole seconds since the GPS epoch.
int leapSecondsForUtcReading(std::int64_t utc_reading_s) {
  const std::int64_t day = floorDiv(utc_reading_s, kSecondsPerDay) + kGpsEpochDays - kDay1972;
  return taiMinusUtcAtUtcDay(day);
}

}  // namespace

std::int64_t daysFromCivil(int year, int month, int day) {
  // Proleptic Gregorian calendar via eras of 400 years (146097 days); the year is
  // counted from March so that the leap day falls at the end of the year.
  const std::int64_t y = static_cast<std::int64_t>(year) - (month <= 2 ? 1 : 0);
  const std::int64_t era = floorDiv(y, 400);
  const std::int64_t year_of_era = y - era * 400;
  const std::int64_t month_from_march = month > 2 ? month - 3 : month + 9;
  const std::int64_t day_of_year = (153 * month_from_march + 2) / 5 + day - 1;
  const std::int64_t day_of_era =
      year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;  // 719468 = days from 0000-03-01 to 1970-01-01
}

bool isValidDate(int year, int month, int day) {
  if (month < 1 || month > 12 || day < 1) return false;
  static const int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  const int max_day = (month == 2 && leap) ? 29 : kDays[month - 1];
  return day <= max_day;
}

GnssTime GnssTime::fromGpsSeconds(std::int64_t whole_s, double fraction_s) {
  GnssTime t;
  std::int64_t extra = 0;
  double frac = 0.0;
  splitSeconds(fraction_s, extra, frac);
  t.whole_s_ = whole_s + extra;
  t.fraction_s_ = frac;
  return t;
}

GnssTime GnssTime::fromGpsWeek(int week, double seconds_of_week) {
  return fromGpsSeconds(static_cast<std::int64_t>(week) * kSecondsPerWeek, seconds_of_week);
}

double GnssTime::offsetToSystem_s(TimeSystem system) const {
  switch (system) {
    case TimeSystem::GPS:
    case TimeSystem::Galileo:
    case TimeSystem::QZSS:
      return 0.0;
    case TimeSystem::BeiDou:
      return -kGpstMinusBdt_s;
    case TimeSystem::TAI:
      return -kGpsMinusTaiS;
    case TimeSystem::UTC:
    case TimeSystem::GLONASS: {
      // UTC = GPST - (TAI-UTC - 19); the leap count is that of the UTC day.
      std::int64_t reading = whole_s_ - 18;
      int leap = leapSecondsForUtcReading(reading);
      reading = whole_s_ - (leap + kGpsMinusTaiS);
      leap = leapSecondsForUtcReading(reading);
      const double utc_offset = -static_cast<double>(leap + kGpsMinusTaiS);
      return system == TimeSystem::UTC ? utc_offset : utc_offset + kGlonassMinusUtc_s;
    }
  }
  return 0.0;
}

GnssTime GnssTime::fromCalendar(const CalendarTime& c, TimeSystem system) {
  if (!isValidDate(c.year, c.month, c.day) || c.hour < 0 || c.hour > 23 || c.minute < 0 ||
      c.minute > 59 || !(c.second >= 0.0) || !(c.second < 61.0)) {
    throw std::invalid_argument("invalid calendar time");
  }
  const std::int64_t days = daysFromCivil(c.year, c.month, c.day) - kGpsEpochDays;
  const std::int64_t reading_whole = days * kSecondsPerDay + c.hour * 3600 + c.minute * 60;
  GnssTime reading = fromGpsSeconds(reading_whole, c.second);
  // Convert the reading in `system` to GPST.
  switch (system) {
    case TimeSystem::GPS:
    case TimeSystem::Galileo:
    case TimeSystem::QZSS:
      return reading;
    case TimeSystem::BeiDou:
      return reading + kGpstMinusBdt_s;
    case TimeSystem::TAI:
      return reading + kGpsMinusTaiS;
    case TimeSystem::UTC:
    case TimeSystem::GLONASS: {
      std::int64_t utc_whole =
          reading_whole - (system == TimeSystem::GLONASS ? static_cast<std::int64_t>(kGlonassMinusUtc_s) : 0);
      const int leap = leapSecondsForUtcReading(utc_whole);
      return fromGpsSeconds(utc_whole + leap + kGpsMinusTaiS, c.second);
    }
  }
  return reading;
}

GnssTime GnssTime::fromMjd(std::int64_t mjd_day, double fraction_of_day, TimeSystem system) {
  // Whole seconds and fraction of the day kept apart to preserve resolution.
  const double day_seconds = fraction_of_day * kSecondsPerDay;
  std::int64_t whole = 0;
  double frac = 0.0;
  splitSeconds(day_seconds, whole, frac);
  const GnssTime reading = fromGpsSeconds((mjd_day - kGpsEpochMjd) * kSecondsPerDay + whole, frac);
  if (system == TimeSystem::GPS || system == TimeSystem::Galileo || system == TimeSystem::QZSS) {
    return reading;
  }
  // Other systems: convert through the calendar path to share the offset logic.
  return fromCalendar(reading.toCalendar(TimeSystem::GPS), system);
}

GpsWeekTime GnssTime::gpsWeek() const {
  GpsWeekTime w;
  const std::int64_t week = floorDiv(whole_s_, kSecondsPerWeek);
  w.week = static_cast<int>(week);
  w.seconds_of_week = static_cast<double>(whole_s_ - week * kSecondsPerWeek) + fraction_s_;
  return w;
}

CalendarTime GnssTime::toCalendar(TimeSystem system) const {
  const GnssTime reading = *this + offsetToSystem_s(system);
  const std::int64_t days = floorDiv(reading.whole_s_, kSecondsPerDay);
  const std::int64_t sod = reading.whole_s_ - days * kSecondsPerDay;
  // Inverse of daysFromCivil.
  const std::int64_t z = days + kGpsEpochDays + 719468;
  const std::int64_t era = floorDiv(z, 146097);
  const std::int64_t doe = z - era * 146097;
  const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const std::int64_t mp = (5 * doy + 2) / 153;
  CalendarTime c;
  c.day = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
  c.month = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  c.year = static_cast<int>(yoe + era * 400 + (c.month <= 2 ? 1 : 0));
  c.hour = static_cast<int>(sod / 3600);
  c.minute = static_cast<int>((sod % 3600) / 60);
  c.second = static_cast<double>(sod % 60) + reading.fraction_s_;
  return c;
}

double GnssTime::mjd(TimeSystem system) const {
  const GnssTime reading = *this + offsetToSystem_s(system);
  const std::int64_t days = floorDiv(reading.whole_s_, kSecondsPerDay);
  const double sod = static_cast<double>(reading.whole_s_ - days * kSecondsPerDay) + reading.fraction_s_;
  return static_cast<double>(days + kGpsEpochMjd) + sod / kSecondsPerDay;
}

int GnssTime::dayOfYear(TimeSystem system) const {
  const CalendarTime c = toCalendar(system);
  return static_cast<int>(daysFromCivil(c.year, c.month, c.day) - daysFromCivil(c.year, 1, 1) + 1);
}

std::string GnssTime::toString(TimeSystem system, int decimals) const {
  // Round the fraction to the printed decimals first and carry a full second
  // into the whole seconds, so that 23:59:59.99996 prints as the next day's
  // 00:00:00.0000 (never as second 60). All system offsets are whole seconds.
  decimals = std::clamp(decimals, 0, 12);
  std::int64_t scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  std::int64_t units = std::llround(fraction_s_ * static_cast<double>(scale));
  const GnssTime whole = fromGpsSeconds(whole_s_ + units / scale);
  units %= scale;
  const CalendarTime c = whole.toCalendar(system);
  char buf[96];
  char fraction[24] = "";
  if (decimals > 0) std::snprintf(fraction, sizeof(fraction), ".%0*lld", decimals, static_cast<long long>(units));
  std::snprintf(buf, sizeof(buf), "%04d-%02d-%02d %02d:%02d:%02d%s %s", c.year, c.month, c.day, c.hour, c.minute,
                static_cast<int>(std::lround(c.second)), fraction, std::string(timeSystemCode(system)).c_str());
  return buf;
}

GnssTime& GnssTime::operator+=(double dt_s) {
  std::int64_t whole = 0;
  double frac = 0.0;
  splitSeconds(dt_s, whole, frac);
  whole_s_ += whole;
  fraction_s_ += frac;
  if (fraction_s_ >= 1.0) {
    fraction_s_ -= 1.0;
    whole_s_ += 1;
  }
  return *this;
}

GnssTime fromBdtWeek(int bdt_week, double bdt_sow) {
  return GnssTime::fromGpsWeek(bdt_week + kBdtWeekZeroGpsWeek, bdt_sow) + kGpstMinusBdt_s;
}

GpsWeekTime toBdtWeek(const GnssTime& t) {
  GpsWeekTime w = (t - kGpstMinusBdt_s).gpsWeek();
  w.week -= kBdtWeekZeroGpsWeek;
  return w;
}

double glonassSecondsOfDay(const GnssTime& t) {
  return std::fmod((t + t.offsetToSystem_s(TimeSystem::GLONASS)).gpsWeek().seconds_of_week,
                   static_cast<double>(kSecondsPerDay));
}

double glonassSecondsOfDayFromUtc(double utc_s) {
  const double day_s = static_cast<double>(kSecondsPerDay);
  return std::fmod(std::fmod(utc_s + kGlonassMinusUtc_s, day_s) + day_s, day_s);
}

GnssTime withinHalfWeek(const GnssTime& near, GnssTime t) {
  const double d = t - near;
  if (d > kSecondsPerWeek / 2) t -= static_cast<double>(kSecondsPerWeek);
  else if (d < -kSecondsPerWeek / 2) t += static_cast<double>(kSecondsPerWeek);
  return t;
}

GnssTime nearestSecondsOfWeek(const GnssTime& near, double sow) {
  return withinHalfWeek(near, GnssTime::fromGpsWeek(near.gpsWeek().week, sow));
}

}  // namespace ppp
