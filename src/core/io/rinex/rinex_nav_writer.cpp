#include "ppp_bayes_tree/io/rinex/rinex_nav_writer.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace ppp {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%19.12E", v);
  return buf;
}

std::string label(std::string text, const char* lbl) {
  text.resize(60, ' ');
  std::string l(lbl);
  l.resize(20, ' ');
  return text + l + "\n";
}

}  // namespace

void RinexNavWriter::writeHeader(const std::string& program) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%9s%11s%-20s%-20s", "3.04", "", "N: GNSS NAV DATA", "M: Mixed");
  out_ << label(buf, "RINEX VERSION / TYPE");
  std::string pgm = program.substr(0, 20);
  pgm.resize(20, ' ');
  out_ << label(pgm, "PGM / RUN BY / DATE");
  out_ << label("", "END OF HEADER");
}

void RinexNavWriter::epochLine(const SatelliteId& sat, const GnssTime& t, TimeSystem system, double a, double b,
                               double c) {
  CalendarTime cal = (t + t.offsetToSystem_s(system)).toCalendar(TimeSystem::GPS);
  // Round to the whole second (RINEX epochs are integral seconds).
  const GnssTime rounded = GnssTime::fromGpsSeconds(
      static_cast<std::int64_t>(std::llround((t + t.offsetToSystem_s(system)).toGpsSecondsDouble())));
  cal = rounded.toCalendar(TimeSystem::GPS);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %04d %02d %02d %02d %02d %02d", sat.toString().c_str(), cal.year, cal.month,
                cal.day, cal.hour, cal.minute, static_cast<int>(cal.second + 0.5));
  out_ << buf << num(a) << num(b) << num(c) << "\n";
}

void RinexNavWriter::orbitLine(double a, double b, double c, double d, int count) {
  out_ << "    " << num(a);
  if (count > 1) out_ << num(b);
  if (count > 2) out_ << num(c);
  if (count > 3) out_ << num(d);
  out_ << "\n";
}

void RinexNavWriter::keplerLines(const SatelliteId& sat, TimeSystem system, const ClockPolynomial& clock,
                                 double issue_of_data, const KeplerOrbit& o) {
  epochLine(sat, clock.toc, system, clock.af0_s, clock.af1_sps, clock.af2_sps2);
  orbitLine(issue_of_data, o.crs_m, o.delta_n_radps, o.m0_rad);
  orbitLine(o.cuc_rad, o.eccentricity, o.cus_rad, o.sqrt_a_sqrtm);
  orbitLine(o.toe_sow, o.cic_rad, o.omega0_rad, o.cis_rad);
  orbitLine(o.i0_rad, o.crc_m, o.omega_rad, o.omega_dot_radps);
}

void RinexNavWriter::write(const GpsLnavEphemeris& e) {
  const KeplerOrbit& o = e.orbit;
  keplerLines(e.satellite, TimeSystem::GPS, e.clock, e.iode, o);
  orbitLine(o.idot_radps, e.codes_on_l2, e.week, e.l2p_data_flag);
  orbitLine(e.ura_m, e.health, e.tgd_s, e.iodc);
  // Fit interval: GPS in hours (RINEX 3.04 A6); QZSS the fit interval flag, 0 = 2 h,
  // 1 = more (A12; IS-QZSS-PNT 4.1.2.4).
  const double fit = e.satellite.system == GnssSystem::QZSS ? (e.fit_interval_h > 2.0 ? 1.0 : 0.0) : e.fit_interval_h;
  orbitLine(e.transmission_sow.value_or(o.toe_sow), fit, 0, 0, 2);
}

void RinexNavWriter::write(const GalileoEphemeris& e) {
  const KeplerOrbit& o = e.orbit;
  keplerLines(e.satellite, TimeSystem::GPS, e.clock, e.iod_nav, o);
  orbitLine(o.idot_radps, e.data_sources, e.week, 0.0, 3);
  orbitLine(e.sisa_m.value_or(-1.0), e.health, e.bgd_e5a_e1_s, e.bgd_e5b_e1_s.value_or(0.0));
  orbitLine(e.transmission_sow.value_or(o.toe_sow), 0, 0, 0, 1);
}

void RinexNavWriter::write(const GlonassEphemeris& e) {
  epochLine(e.satellite, e.tb, TimeSystem::UTC, e.minus_tau_n_s, e.gamma_n, e.message_frame_time_s);
  const Eigen::Vector3d p = e.position_m * 1e-3, v = e.velocity_mps * 1e-3, a = e.acceleration_mps2 * 1e-3;
  orbitLine(p.x(), v.x(), a.x(), e.health);
  orbitLine(p.y(), v.y(), a.y(), e.frequency_channel);
  orbitLine(p.z(), v.z(), a.z(), e.age_days);
}

void RinexNavWriter::write(const BeidouEphemeris& e) {
  const KeplerOrbit& o = e.orbit;
  keplerLines(e.satellite, TimeSystem::BeiDou, e.clock, e.aode, o);
  orbitLine(o.idot_radps, 0.0, e.bdt_week, 0.0);
  orbitLine(e.ura_m, e.health, e.tgd1_s, e.tgd2_s);
  // Transmission time: RTCM 1042 carries none; toe then stands in (as for the other systems).
  orbitLine(e.transmission_sow.value_or(o.toe_sow), e.aodc, 0, 0, 2);
}

}  // namespace ppp
