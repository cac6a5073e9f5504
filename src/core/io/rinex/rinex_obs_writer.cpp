#include "ppp_bayes_tree/io/rinex/rinex_obs_writer.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace ppp {
namespace {

std::string label(std::string text, const char* label_text) {
  text.resize(60, ' ');
  std::string lbl(label_text);
  lbl.resize(20, ' ');
  return text + lbl + "\n";
}

std::string fit(const std::string& s, std::size_t width) {
  std::string out = s.substr(0, width);
  out.resize(width, ' ');
  return out;
}

}  // namespace

void RinexObsWriter::writeHeader(const RinexObsHeader& h) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%9s%11s%-20s%-20s", "3.04", "", "OBSERVATION DATA", "M: Mixed");
  out_ << label(buf, "RINEX VERSION / TYPE");
  out_ << label(fit(h.program.empty() ? "ppp_bayes_tree" : h.program, 20) + fit(h.run_by, 20) + fit(h.date, 20),
                "PGM / RUN BY / DATE");
  for (const auto& c : h.comments) out_ << label(fit(c, 60), "COMMENT");
  out_ << label(fit(h.marker_name, 60), "MARKER NAME");
  if (!h.marker_number.empty()) out_ << label(fit(h.marker_number, 20), "MARKER NUMBER");
  out_ << label(fit(h.marker_type, 20), "MARKER TYPE");
  out_ << label(fit(h.observer, 20) + fit(h.agency, 40), "OBSERVER / AGENCY");
  out_ << label(fit(h.receiver_number, 20) + fit(h.receiver_type, 20) + fit(h.receiver_version, 20),
                "REC # / TYPE / VERS");
  out_ << label(fit(h.antenna_number, 20) + fit(h.antenna_type, 16) + fit(h.antenna_radome, 4), "ANT # / TYPE");
  const Eigen::Vector3d xyz = h.approx_position_ecef_m.value_or(Eigen::Vector3d::Zero());
  std::snprintf(buf, sizeof buf, "%14.4f%14.4f%14.4f", xyz.x(), xyz.y(), xyz.z());
  out_ << label(buf, "APPROX POSITION XYZ");
  const Eigen::Vector3d hen = h.antenna_delta_hen_m.value_or(Eigen::Vector3d::Zero());
  std::snprintf(buf, sizeof buf, "%14.4f%14.4f%14.4f", hen.x(), hen.y(), hen.z());
  out_ << label(buf, "ANTENNA: DELTA H/E/N");
  for (int s = 0; s < kNumGnssSystems; ++s) {
    const auto& types = h.obs_types[s];
    if (types.empty()) continue;
    for (std::size_t i = 0; i < types.size(); i += 13) {
      std::string line = i == 0 ? std::string(1, systemLetter(static_cast<GnssSystem>(s))) : " ";
      if (i == 0) {
        std::snprintf(buf, sizeof buf, "  %3zu", types.size());
        line += buf;
      } else {
        line += "     ";
      }
      for (std::size_t k = i; k < types.size() && k < i + 13; ++k) line += " " + types[k].toString();
      out_ << label(line, "SYS / # / OBS TYPES");
    }
  }
  if (!h.signal_strength_unit.empty()) out_ << label(fit(h.signal_strength_unit, 20), "SIGNAL STRENGTH UNIT");
  if (h.interval_s) {
    std::snprintf(buf, sizeof buf, "%10.3f", *h.interval_s);
    out_ << label(buf, "INTERVAL");
  }
  auto timeLine = [&](const RinexHeaderTime& t, const char* name) {
    const CalendarTime c = t.time.toCalendar(TimeSystem::GPS);
    std::snprintf(buf, sizeof buf, "  %4d    %2d    %2d    %2d    %2d   %10.7f     GPS", c.year, c.month, c.day,
                  c.hour, c.minute, c.second);
    out_ << label(buf, name);
  };
  if (h.time_of_first_obs) timeLine(*h.time_of_first_obs, "TIME OF FIRST OBS");
  if (h.time_of_last_obs) timeLine(*h.time_of_last_obs, "TIME OF LAST OBS");
  for (int s = 0; s < kNumGnssSystems; ++s) {
    for (const auto& code : h.obs_types[s]) {
      if (code.type != ObservableType::CarrierPhase) continue;
      std::string line = std::string(1, systemLetter(static_cast<GnssSystem>(s))) + " " + code.toString();
      out_ << label(line, "SYS / PHASE SHIFT");
    }
  }
  if (!h.types(GnssSystem::GLONASS).empty()) {
    std::vector<std::pair<int, int>> slots;
    for (int slot = 1; slot <= GlonassChannels::kMaxSlot; ++slot)
      if (const auto k = h.glonass_channels.channel(slot)) slots.emplace_back(slot, *k);
    std::size_t i = 0;
    do {
      std::string line;
      if (i == 0) {
        std::snprintf(buf, sizeof buf, "%3zu ", slots.size());
        line = buf;
      } else {
        line = "    ";
      }
      for (std::size_t k = i; k < slots.size() && k < i + 8; ++k) {
        std::snprintf(buf, sizeof buf, "R%02d %2d ", slots[k].first, slots[k].second);
        line += buf;
      }
      out_ << label(line, "GLONASS SLOT / FRQ #");
      i += 8;
    } while (i < slots.size());
    out_ << label(" C1C    0.000 C1P    0.000 C2C    0.000 C2P    0.000", "GLONASS COD/PHS/BIS");
  }
  if (h.leap_seconds) {
    std::snprintf(buf, sizeof buf, "%6d", *h.leap_seconds);
    out_ << label(buf, "LEAP SECONDS");
  }
  out_ << label("", "END OF HEADER");
}

void RinexObsWriter::writeEpoch(const ObsEpoch& epoch, const RinexObsHeader& h) {
  std::size_t n = 0;
  for (const auto& s : epoch.satellites)
    if (!h.types(s.satellite.system).empty()) ++n;
  const CalendarTime c = epoch.time.toCalendar(TimeSystem::GPS);
  char buf[160];
  std::snprintf(buf, sizeof buf, "> %04d %02d %02d %02d %02d%11.7f  %d%3zu", c.year, c.month, c.day, c.hour,
                c.minute, c.second, static_cast<int>(epoch.flag), n);
  out_ << buf;
  if (epoch.receiver_clock_offset_s) {
    std::snprintf(buf, sizeof buf, "      %15.12f", *epoch.receiver_clock_offset_s);
    out_ << buf;
  }
  out_ << "\n";
  std::string line;
  for (std::size_t i = 0; i < epoch.satellites.size(); ++i) {
    const auto& s = epoch.satellites[i];
    const auto& types = h.types(s.satellite.system);
    if (types.empty()) continue;
    line = s.satellite.toString();
    const Observation* obs = epoch.begin(i);
    for (std::size_t k = 0; k < types.size(); ++k) {
      if (k < s.count && obs[k].value && std::fabs(*obs[k].value) < 1e9) {
        std::snprintf(buf, sizeof buf, "%14.3f", *obs[k].value);
        line += buf;
      } else {
        line += "              ";
      }
      const bool lli = k < s.count && obs[k].lli && *obs[k].lli != 0;
      line += lli ? static_cast<char>('0' + (*obs[k].lli % 10)) : ' ';
      const bool ssi = k < s.count && obs[k].ssi && *obs[k].ssi != 0;
      line += ssi ? static_cast<char>('0' + (*obs[k].ssi % 10)) : ' ';
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out_ << line << "\n";
  }
}

}  // namespace ppp
