#include "ppp_bayes_tree/io/rtcm/rtcm3_ephemeris_encoder.h"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/types/constants.h"
#include "rtcm3_ephemeris_layout.h"

namespace ppp {
namespace {

using rtcm_eph::p2;
using rtcm_eph::q;
using rtcm_eph::semicircles;

double secondsOfWeek(const GnssTime& t) { return t.gpsWeek().seconds_of_week; }

}  // namespace

int ephemerisMessageType(const GpsLnavEphemeris& eph) {
  return eph.satellite.system == GnssSystem::QZSS ? 1044 : 1019;
}
int ephemerisMessageType(const GlonassEphemeris&) { return 1020; }
int ephemerisMessageType(const GalileoEphemeris& eph) { return eph.type == GalileoNavType::FNav ? 1045 : 1046; }
int ephemerisMessageType(const BeidouEphemeris&) { return 1042; }

std::vector<std::uint8_t> encodeEphemerisPayload(const GpsLnavEphemeris& e) {
  const bool qzss = e.satellite.system == GnssSystem::QZSS;
  if (qzss ? (e.satellite.prn < 1 || e.satellite.prn > 10)
           : (e.satellite.system != GnssSystem::GPS || e.satellite.prn < 1 || e.satellite.prn > 32)) {
    throw std::invalid_argument("1019/1044 ephemeris: no satellite number for " + e.satellite.toString());
  }
  const KeplerOrbit& o = e.orbit;
  const int week10 = o.toe.gpsWeek().week % 1024;
  const std::int64_t toc16 = q(secondsOfWeek(e.clock.toc), 16.0);
  BitWriter w;
  w.putUnsigned(static_cast<std::uint64_t>(ephemerisMessageType(e)), 12);
  if (!qzss) {
    w.putUnsigned(static_cast<std::uint64_t>(e.satellite.prn), 6);
    w.putUnsigned(static_cast<std::uint64_t>(week10), 10);
    w.putUnsigned(static_cast<std::uint64_t>(gpsUraIndex(e.ura_m)), 4);
    w.putUnsigned(static_cast<std::uint64_t>(e.codes_on_l2), 2);
    w.putSigned(semicircles(o.idot_radps, -43), 14);
    w.putUnsigned(static_cast<std::uint64_t>(e.iode), 8);
    w.putUnsigned(static_cast<std::uint64_t>(toc16), 16);
    w.putSigned(q(e.clock.af2_sps2, p2(-55)), 8);
    w.putSigned(q(e.clock.af1_sps, p2(-43)), 16);
    w.putSigned(q(e.clock.af0_s, p2(-31)), 22);
    w.putUnsigned(static_cast<std::uint64_t>(e.iodc), 10);
  } else {
    w.putUnsigned(static_cast<std::uint64_t>(e.satellite.prn), 4);
    w.putUnsigned(static_cast<std::uint64_t>(toc16), 16);
    w.putSigned(q(e.clock.af2_sps2, p2(-55)), 8);
    w.putSigned(q(e.clock.af1_sps, p2(-43)), 16);
    w.putSigned(q(e.clock.af0_s, p2(-31)), 22);
    w.putUnsigned(static_cast<std::uint64_t>(e.iode), 8);
  }
  rtcm_eph::putKepler(w, rtcm_eph::kKeplerLnav, o);
  if (!qzss) {
    w.putSigned(q(e.tgd_s, p2(-31)), 8);
    w.putUnsigned(static_cast<std::uint64_t>(e.health), 6);
    w.putUnsigned(static_cast<std::uint64_t>(e.l2p_data_flag), 1);
    w.putFlag(e.fit_interval_h > 4.0);  // DF137: 0 = 4 h, 1 = more than 4 h
  } else {
    w.putSigned(semicircles(o.idot_radps, -43), 14);
    w.putUnsigned(static_cast<std::uint64_t>(e.codes_on_l2), 2);
    w.putUnsigned(static_cast<std::uint64_t>(week10), 10);
    w.putUnsigned(static_cast<std::uint64_t>(gpsUraIndex(e.ura_m)), 4);
    w.putUnsigned(static_cast<std::uint64_t>(e.health), 6);
    w.putSigned(q(e.tgd_s, p2(-31)), 8);
    w.putUnsigned(static_cast<std::uint64_t>(e.iodc), 10);
    w.putFlag(e.fit_interval_h > 2.0);  // DF187: 0 = 2 h, 1 = more than 2 h
  }
  return w.bytes();
}

std::vector<std::uint8_t> encodeEphemerisPayload(const GlonassEphemeris& g) {
  if (g.satellite.system != GnssSystem::GLONASS || g.satellite.prn < 1 || g.satellite.prn > 63)
    throw std::invalid_argument("1020 ephemeris: no slot number for " + g.satellite.toString());
  // tk: RINEX gives the message frame time as seconds of the UTC week (or day);
  // the message holds the Moscow time of day in 30-s steps.
  const double tk_tod = glonassSecondsOfDayFromUtc(g.message_frame_time_s);
  const int tk_s = static_cast<int>(std::floor(tk_tod + 1e-6));
  // tb: the Moscow time of day of the reference epoch in 15-min steps (1..96).
  int tb = static_cast<int>(std::lround(glonassSecondsOfDay(g.tb) / 900.0));
  if (tb == 0) tb = 96;  // 24:00 of the day before: the same instant modulo the day
  BitWriter w;
  w.putUnsigned(1020, 12);
  w.putUnsigned(static_cast<std::uint64_t>(g.satellite.prn), 6);
  w.putUnsigned(static_cast<std::uint64_t>(g.frequency_channel + 7), 5);
  w.putUnsigned(0, 1);  // almanac health
  w.putUnsigned(0, 1);  // almanac health availability
  w.putUnsigned(0, 2);  // P1
  w.putUnsigned(static_cast<std::uint64_t>(tk_s / 3600), 5);
  w.putUnsigned(static_cast<std::uint64_t>((tk_s % 3600) / 60), 6);
  w.putUnsigned((tk_s % 60) >= 30 ? 1u : 0u, 1);
  w.putUnsigned(static_cast<std::uint64_t>(g.health & 1), 1);  // Bn MSB
  w.putUnsigned(0, 1);                                          // P2
  w.putUnsigned(static_cast<std::uint64_t>(tb), 7);
  for (int axis = 0; axis < 3; ++axis) {
    w.putSignMagnitude(q(g.velocity_mps[axis] * 1e-3, p2(-20)), 24);
    w.putSignMagnitude(q(g.position_m[axis] * 1e-3, p2(-11)), 27);
    w.putSignMagnitude(q(g.acceleration_mps2[axis] * 1e-3, p2(-30)), 5);
  }
  w.putUnsigned(0, 1);  // P3
  w.putSignMagnitude(q(g.gamma_n, p2(-40)), 11);
  w.putUnsigned(0, 2);  // P
  w.putUnsigned(0, 1);  // ln (third string)
  w.putSignMagnitude(q(-g.minus_tau_n_s, p2(-30)), 22);
  w.putSignMagnitude(0, 5);  // delta tau
  w.putUnsigned(static_cast<std::uint64_t>(std::lround(g.age_days)), 5);
  // Fields no decoder of ours reads, present so that the message has its full
  // 360 bits (RTCM 10403.3 table 3.5-12): P4, FT, NT, M, additional data
  // availability, NA, tauC, N4, tauGPS, ln (fifth string), reserved.
  w.putUnsigned(0, 1);
  w.putUnsigned(15, 4);  // FT: accuracy not given
  w.putUnsigned(0, 11);
  w.putUnsigned(1, 2);  // M: GLONASS-M
  w.putUnsigned(0, 1);  // no additional data
  w.putUnsigned(0, 11);
  w.putSignMagnitude(0, 32);
  w.putUnsigned(0, 5);
  w.putSignMagnitude(0, 22);
  w.putUnsigned(0, 1);
  w.putUnsigned(0, 7);
  return w.bytes();
}

std::vector<std::uint8_t> encodeEphemerisPayload(const GalileoEphemeris& e) {
  if (e.satellite.system != GnssSystem::Galileo || e.satellite.prn < 1 || e.satellite.prn > 63)
    throw std::invalid_argument("1045/1046 ephemeris: no satellite number for " + e.satellite.toString());
  const KeplerOrbit& o = e.orbit;
  const bool fnav = e.type == GalileoNavType::FNav;
  const int gst_week = ((o.toe.gpsWeek().week - 1024) % 4096 + 4096) % 4096;
  BitWriter w;
  w.putUnsigned(static_cast<std::uint64_t>(ephemerisMessageType(e)), 12);
  w.putUnsigned(static_cast<std::uint64_t>(e.satellite.prn), 6);
  w.putUnsigned(static_cast<std::uint64_t>(gst_week), 12);
  w.putUnsigned(static_cast<std::uint64_t>(e.iod_nav), 10);
  w.putUnsigned(static_cast<std::uint64_t>(galileoSisaIndex(e.sisa_m)), 8);
  w.putSigned(semicircles(o.idot_radps, -43), 14);
  w.putUnsigned(static_cast<std::uint64_t>(q(secondsOfWeek(e.clock.toc), 60.0)), 14);
  w.putSigned(q(e.clock.af2_sps2, p2(-59)), 6);
  w.putSigned(q(e.clock.af1_sps, p2(-46)), 21);
  w.putSigned(q(e.clock.af0_s, p2(-34)), 31);
  rtcm_eph::putKepler(w, rtcm_eph::kKeplerGalileo, o);
  w.putSigned(q(e.bgd_e5a_e1_s, p2(-32)), 10);
  if (fnav) {
    w.putUnsigned(static_cast<std::uint64_t>((e.health >> 4) & 3), 2);  // E5a HS
    w.putUnsigned(static_cast<std::uint64_t>((e.health >> 3) & 1), 1);  // E5a DVS
    w.putUnsigned(0, 7);                                                // reserved
  } else {
    w.putSigned(q(e.bgd_e5b_e1_s.value_or(0.0), p2(-32)), 10);
    w.putUnsigned(static_cast<std::uint64_t>((e.health >> 7) & 3), 2);  // E5b HS
    w.putUnsigned(static_cast<std::uint64_t>((e.health >> 6) & 1), 1);  // E5b DVS
    w.putUnsigned(static_cast<std::uint64_t>((e.health >> 1) & 3), 2);  // E1-B HS
    w.putUnsigned(static_cast<std::uint64_t>(e.health & 1), 1);         // E1-B DVS
    w.putUnsigned(0, 2);                                                // reserved
  }
  return w.bytes();
}

std::vector<std::uint8_t> encodeEphemerisPayload(const BeidouEphemeris& e) {
  if (e.satellite.system != GnssSystem::BeiDou || e.satellite.prn < 1 || e.satellite.prn > 63)
    throw std::invalid_argument("1042 ephemeris: no satellite number for " + e.satellite.toString());
  const KeplerOrbit& o = e.orbit;
  const double toc_bdt_sow = toBdtWeek(e.clock.toc).seconds_of_week;
  BitWriter w;
  w.putUnsigned(1042, 12);
  w.putUnsigned(static_cast<std::uint64_t>(e.satellite.prn), 6);
  w.putUnsigned(static_cast<std::uint64_t>(((e.bdt_week % 8192) + 8192) % 8192), 13);
  w.putUnsigned(static_cast<std::uint64_t>(beidouUraIndex(e.ura_m)), 4);
  w.putSigned(semicircles(o.idot_radps, -43), 14);
  w.putUnsigned(static_cast<std::uint64_t>(e.aode), 5);
  w.putUnsigned(static_cast<std::uint64_t>(q(toc_bdt_sow, 8.0)), 17);
  w.putSigned(q(e.clock.af2_sps2, p2(-66)), 11);
  w.putSigned(q(e.clock.af1_sps, p2(-50)), 22);
  w.putSigned(q(e.clock.af0_s, p2(-33)), 24);
  w.putUnsigned(static_cast<std::uint64_t>(e.aodc), 5);
  rtcm_eph::putKepler(w, rtcm_eph::kKeplerBeidou, o);
  w.putSigned(q(e.tgd1_s, 1e-10), 10);
  w.putSigned(q(e.tgd2_s, 1e-10), 10);
  w.putUnsigned(static_cast<std::uint64_t>(e.health & 1), 1);
  return w.bytes();
}

}  // namespace ppp
