#include "ppp_bayes_tree/types/satellite_id.h"

#include <cstdio>

namespace ppp {

char systemLetter(GnssSystem system) {
  switch (system) {
    case GnssSystem::GPS: return 'G';
    case GnssSystem::GLONASS: return 'R';
    case GnssSystem::Galileo: return 'E';
    case GnssSystem::BeiDou: return 'C';
    case GnssSystem::QZSS: return 'J';
    case GnssSystem::SBAS: return 'S';
    case GnssSystem::IRNSS: return 'I';
  }
  return '?';
}

std::optional<GnssSystem> systemFromLetter(char letter) {
  switch (letter) {
    case 'G': return GnssSystem::GPS;
    case 'R': return GnssSystem::GLONASS;
    case 'E': return GnssSystem::Galileo;
    case 'C': return GnssSystem::BeiDou;
    case 'J': return GnssSystem::QZSS;
    case 'S': return GnssSystem::SBAS;
    case 'I': return GnssSystem::IRNSS;
    default: return std::nullopt;
  }
}

std::string_view systemName(GnssSystem system) {
  switch (system) {
    case GnssSystem::GPS: return "GPS";
    case GnssSystem::GLONASS: return "GLONASS";
    case GnssSystem::Galileo: return "Galileo";
    case GnssSystem::BeiDou: return "BeiDou";
    case GnssSystem::QZSS: return "QZSS";
    case GnssSystem::SBAS: return "SBAS";
    case GnssSystem::IRNSS: return "IRNSS";
  }
  return "unknown";
}

int SatelliteId::maxPrn(GnssSystem system) {
  switch (system) {
    case GnssSystem::GPS: return 32;
    case GnssSystem::GLONASS: return 30;  // slots 1-24 in use, spares up to 30
    case GnssSystem::Galileo: return 36;
    case GnssSystem::BeiDou: return 65;
    case GnssSystem::QZSS: return 10;
    case GnssSystem::SBAS: return 58;     // PRN 120-158
    case GnssSystem::IRNSS: return 14;
  }
  return 0;
}

std::optional<SatelliteId> SatelliteId::parse(std::string_view text) {
  if (text.empty()) return std::nullopt;
  SatelliteId id;
  std::size_t pos = 0;
  if (text[0] == ' ' || (text[0] >= '0' && text[0] <= '9')) {
    id.system = GnssSystem::GPS;  // RINEX 2: blank means GPS
    pos = text[0] == ' ' ? 1 : 0;
  } else {
    auto sys = systemFromLetter(text[0]);
    if (!sys) return std::nullopt;
    id.system = *sys;
    pos = 1;
  }
  while (pos < text.size() && text[pos] == ' ') ++pos;
  if (pos >= text.size()) return std::nullopt;
  int value = 0;
  int digits = 0;
  for (; pos < text.size(); ++pos) {
    const char c = text[pos];
    if (c == ' ') break;
    if (c < '0' || c > '9' || ++digits > 3) return std::nullopt;
    value = value * 10 + (c - '0');
  }
  for (; pos < text.size(); ++pos) {
    if (text[pos] != ' ') return std::nullopt;
  }
  if (digits == 0) return std::nullopt;
  // SBAS and QZSS are sometimes written with their full PRN (120-158, 193-202).
  if (id.system == GnssSystem::SBAS && value >= 100) value -= 100;
  if (id.system == GnssSystem::QZSS && value >= 193) value -= 192;
  if (value < 1 || value > maxPrn(id.system)) return std::nullopt;
  id.prn = value;
  return id;
}

std::string SatelliteId::toString() const {
  char buf[8];
  std::snprintf(buf, sizeof(buf), "%c%02d", systemLetter(system), prn % 100);
  return buf;
}

}  // namespace ppp
