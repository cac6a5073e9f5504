// GnssTime: calendar, GPS week, MJD, day of year and time-system conversions,
// checked against published dates.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/types/gnss_time.h"

using ppp::CalendarTime;
using ppp::GnssTime;
using ppp::TimeSystem;

TEST(GnssTime, GpsEpochIsWeekZero) {
  const GnssTime t = GnssTime::fromCalendar({1980, 1, 6, 0, 0, 0.0});
  EXPECT_EQ(t.wholeSeconds(), 0);
  EXPECT_EQ(t.gpsWeek().week, 0);
  EXPECT_DOUBLE_EQ(t.mjd(), 44244.0);  // MJD of 1980-01-06 (IS-GPS-200 epoch)
}

TEST(GnssTime, ZimDayIsGpsWeek2418Day3) {
  // Dataset README: 2026-05-13 is GPS week 2418, day 3 (Wednesday); DOY 133.
  const GnssTime t = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});
  const auto w = t.gpsWeek();
  EXPECT_EQ(w.week, 2418);
  EXPECT_DOUBLE_EQ(w.seconds_of_week, 3 * 86400.0);
  EXPECT_EQ(t.dayOfYear(), 133);
  // MJD 61173 = 2026-05-13 (MJD 60676 = 2025-01-01, +365 + 132).
  EXPECT_DOUBLE_EQ(t.mjd(), 61173.0);
}

TEST(GnssTime, Ccj2DayIsGpsWeek2168Day4) {
  // 2021-07-29 = GPS week 2168, day 4, DOY 210 (file name ccj22100.21o).
  const GnssTime t = GnssTime::fromCalendar({2021, 7, 29, 0, 0, 0.0});
  EXPECT_EQ(t.gpsWeek().week, 2168);
  EXPECT_DOUBLE_EQ(t.gpsWeek().seconds_of_week, 4 * 86400.0);
  EXPECT_EQ(t.dayOfYear(), 210);
}

TEST(GnssTime, WeekRolloverDates) {
  // First GPS week roll-over: week 1024 started 1999-08-22; second: 2019-04-07.
  EXPECT_EQ(GnssTime::fromCalendar({1999, 8, 22, 0, 0, 0.0}).gpsWeek().week, 1024);
  EXPECT_EQ(GnssTime::fromCalendar({2019, 4, 7, 0, 0, 0.0}).gpsWeek().week, 2048);
}

TEST(GnssTime, CalendarRoundTrip) {
  const CalendarTime c{2024, 2, 29, 23, 59, 59.1234567};
  const CalendarTime r = GnssTime::fromCalendar(c).toCalendar();
  EXPECT_EQ(r.year, 2024);
  EXPECT_EQ(r.month, 2);
  EXPECT_EQ(r.day, 29);
  EXPECT_EQ(r.hour, 23);
  EXPECT_EQ(r.minute, 59);
  EXPECT_NEAR(r.second, 59.1234567, 1e-9);
  EXPECT_THROW(GnssTime::fromCalendar({2023, 2, 29, 0, 0, 0.0}), std::invalid_argument);
}

TEST(GnssTime, UtcLeapSeconds) {
  // GPS-UTC = 18 s since 2017-01-01 (IERS Bulletin C 52), 17 s in 2016.
  const GnssTime t = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});
  EXPECT_DOUBLE_EQ(t.offsetToSystem_s(TimeSystem::UTC), -18.0);
  const GnssTime t16 = GnssTime::fromCalendar({2016, 6, 1, 0, 0, 0.0});
  EXPECT_DOUBLE_EQ(t16.offsetToSystem_s(TimeSystem::UTC), -17.0);
  // UTC reading converts back to the same instant.
  const GnssTime from_utc = GnssTime::fromCalendar({2026, 5, 12, 23, 59, 42.0}, TimeSystem::UTC);
  EXPECT_EQ(from_utc, t);
  // The leap second 2016-12-31 23:59:60 UTC is a distinct instant before 2017-01-01 00:00:00.
  const GnssTime leap = GnssTime::fromCalendar({2016, 12, 31, 23, 59, 60.0}, TimeSystem::UTC);
  const GnssTime after = GnssTime::fromCalendar({2017, 1, 1, 0, 0, 0.0}, TimeSystem::UTC);
  EXPECT_DOUBLE_EQ(after - leap, 1.0);
}

TEST(GnssTime, BeiDouGalileoGlonassOffsets) {
  const GnssTime t = GnssTime::fromCalendar({2021, 7, 29, 0, 0, 0.0});
  // BDT = GPST - 14 s (BDS-SIS-ICD): 00:00:00 GPST reads 23:59:46 BDT the day before.
  const CalendarTime bdt = t.toCalendar(TimeSystem::BeiDou);
  EXPECT_EQ(bdt.day, 28);
  EXPECT_EQ(bdt.hour, 23);
  EXPECT_EQ(bdt.minute, 59);
  EXPECT_DOUBLE_EQ(bdt.second, 46.0);
  EXPECT_EQ(GnssTime::fromCalendar(bdt, TimeSystem::BeiDou), t);
  EXPECT_DOUBLE_EQ(t.offsetToSystem_s(TimeSystem::Galileo), 0.0);
  // GLONASS time = UTC + 3 h.
  EXPECT_DOUBLE_EQ(t.offsetToSystem_s(TimeSystem::GLONASS), 3 * 3600.0 - 18.0);
  EXPECT_EQ(GnssTime::fromCalendar(t.toCalendar(TimeSystem::GLONASS), TimeSystem::GLONASS), t);
}

TEST(GnssTime, NanosecondsSurviveDaysOfArithmetic) {
  GnssTime t = GnssTime::fromCalendar({2026, 5, 13, 0, 0, 0.0});
  const GnssTime start = t;
  // One million 0.1 s steps (27.8 h): the fraction must stay exact to < 1 ns.
  for (int i = 0; i < 1000000; ++i) t += 0.1;
  EXPECT_NEAR(t - start, 100000.0, 1e-6);
  GnssTime u = start + 86400.0 * 3 + 1e-9;
  EXPECT_EQ(u.wholeSeconds() - start.wholeSeconds(), 3 * 86400);
  EXPECT_NEAR(u.fraction(), 1e-9, 1e-15);
  EXPECT_NEAR((u - start) - 3 * 86400.0, 1e-9, 1e-10);  // double resolution at 2.6e5 s is 3e-11 s
}

TEST(GnssTime, MjdRoundTrip) {
  const GnssTime t = GnssTime::fromMjd(61173, 0.5);
  EXPECT_EQ(t, GnssTime::fromCalendar({2026, 5, 13, 12, 0, 0.0}));
  EXPECT_EQ(t.toString(), "2026-05-13 12:00:00.0000000 GPS");
}

// Rounding to the printed decimals carries into minute, hour, day, month and
// year: the text never shows second 60 (the formatter once printed 23:45:60).
TEST(GnssTime, ToStringRoundingCarriesIntoMinuteHourDayAndYear) {
  const GnssTime minute = GnssTime::fromCalendar({2020, 6, 25, 23, 46, 0.0});
  EXPECT_EQ((minute - 0.4).toString(TimeSystem::GPS, 0), "2020-06-25 23:46:00 GPS");      // 59.6 s
  EXPECT_EQ((minute - 0.9999).toString(TimeSystem::GPS, 0), "2020-06-25 23:45:59 GPS");   // 59.0001 s
  EXPECT_EQ((minute - 0.00004).toString(TimeSystem::GPS, 4), "2020-06-25 23:46:00.0000 GPS");
  EXPECT_EQ((minute - 0.0001).toString(TimeSystem::GPS, 3), "2020-06-25 23:46:00.000 GPS");
  EXPECT_EQ((minute - 0.0001).toString(TimeSystem::GPS, 4), "2020-06-25 23:45:59.9999 GPS");
  const GnssTime new_year = GnssTime::fromCalendar({2021, 1, 1, 0, 0, 0.0});
  EXPECT_EQ((new_year - 0.0004).toString(TimeSystem::GPS, 3), "2021-01-01 00:00:00.000 GPS");
  EXPECT_EQ((new_year - 0.0006).toString(TimeSystem::GPS, 3), "2020-12-31 23:59:59.999 GPS");
  EXPECT_EQ((new_year - 0.6).toString(TimeSystem::GPS, 0), "2020-12-31 23:59:59 GPS");
  EXPECT_EQ((new_year - 0.4).toString(TimeSystem::GPS, 0), "2021-01-01 00:00:00 GPS");
  EXPECT_EQ((new_year - 0.0004).toString(), "2020-12-31 23:59:59.9996000 GPS");  // default 7 decimals
  // In another time system the carry happens on that system's reading.
  const GnssTime utc_new_year = GnssTime::fromCalendar({2021, 1, 1, 0, 0, 0.0}, TimeSystem::UTC);
  EXPECT_EQ((utc_new_year - 0.00002).toString(TimeSystem::UTC, 4), "2021-01-01 00:00:00.0000 UTC");
  EXPECT_EQ((minute + 0.25).toString(TimeSystem::GPS, 2), "2020-06-25 23:46:00.25 GPS");
}
