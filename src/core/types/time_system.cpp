#include "ppp_bayes_tree/types/time_system.h"

#include <array>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

namespace {
/// GPST minus the system's time of week, indexed by GnssSystem (header above).
constexpr std::array<std::optional<double>, kNumGnssSystems> kGpstMinusWeekTime_s = {
    0.0,              // GPS
    std::nullopt,     // GLONASS: a time of day, with UTC's leap seconds
    0.0,              // Galileo GST
    kGpstMinusBdt_s,  // BeiDou BDT
    0.0,              // QZSS
    0.0,              // SBAS (network time steered to GPST)
    0.0,              // NavIC (IRNWT, week aligned with GPST)
};
}  // namespace

std::optional<double> gpstMinusWeekTime_s(GnssSystem system) {
  return kGpstMinusWeekTime_s[static_cast<std::size_t>(system)];
}

std::string_view timeSystemCode(TimeSystem system) {
  switch (system) {
    case TimeSystem::GPS: return "GPS";
    case TimeSystem::Galileo: return "GAL";
    case TimeSystem::BeiDou: return "BDT";
    case TimeSystem::QZSS: return "QZS";
    case TimeSystem::UTC: return "UTC";
    case TimeSystem::GLONASS: return "GLO";
    case TimeSystem::TAI: return "TAI";
  }
  return "???";
}

std::optional<TimeSystem> parseTimeSystem(std::string_view code) {
  if (code == "GPS") return TimeSystem::GPS;
  if (code == "GAL") return TimeSystem::Galileo;
  if (code == "BDT") return TimeSystem::BeiDou;
  if (code == "QZS") return TimeSystem::QZSS;
  if (code == "UTC") return TimeSystem::UTC;
  if (code == "GLO") return TimeSystem::GLONASS;
  if (code == "TAI") return TimeSystem::TAI;
  return std::nullopt;
}

namespace {
struct LeapEntry {
  int year, month;  // first day (UTC) on which the value holds
  int tai_minus_utc_s;
};
// IERS Bulletin C (Paris Observatory); TAI-UTC since 1972.
constexpr std::array<LeapEntry, 28> kLeapTable{{
    {1972, 1, 10}, {1972, 7, 11}, {1973, 1, 12}, {1974, 1, 13}, {1975, 1, 14},
    {1976, 1, 15}, {1977, 1, 16}, {1978, 1, 17}, {1979, 1, 18}, {1980, 1, 19},
    {1981, 7, 20}, {1982, 7, 21}, {1983, 7, 22}, {1985, 7, 23}, {1988, 1, 24},
    {1990, 1, 25}, {1991, 1, 26}, {1992, 7, 27}, {1993, 7, 28}, {1994, 7, 29},
    {1996, 1, 30}, {1997, 7, 31}, {1999, 1, 32}, {2006, 1, 33}, {2009, 1, 34},
    {2012, 7, 35}, {2015, 7, 36}, {2017, 1, 37},
}};
const std::int64_t kDay1972 = daysFromCivil(1972, 1, 1);
}  // namespace

int taiMinusUtcAtUtcDay(std::int64_t days_since_1972) {
  int value = 10;
  for (const auto& e : kLeapTable) {
    if (days_since_1972 >= daysFromCivil(e.year, e.month, 1) - kDay1972) value = e.tai_minus_utc_s;
  }
  return value;
}

std::int64_t leapTableValidUntilDay() {
  // Bulletin C 71 announced no leap second up to 2026-12-31.
  return daysFromCivil(2026, 12, 31) - kDay1972;
}

}  // namespace ppp
