#include "ppp_bayes_tree/types/satellite_id.h"

#include <cstdio>

namespace ppp {

namespace {

/// One row per system, in the order of GnssSystem.
struct SystemRow {
  GnssSystem system;
  char letter;            // RINEX 3.05 sec. 3.5
  std::string_view name;
  int max_prn;            // largest number accepted
  int full_prn_offset;    // numbers above it are full PRNs written instead (SBAS 120-158, QZSS 193-202); 0: none
};

constexpr SystemRow kSystems[kNumGnssSystems] = {
    {GnssSystem::GPS, 'G', "GPS", 32, 0},
    {GnssSystem::GLONASS, 'R', "GLONASS", 30, 0},  // slots 1-24 in use, spares up to 30
    {GnssSystem::Galileo, 'E', "Galileo", 36, 0},
    {GnssSystem::BeiDou, 'C', "BeiDou", 65, 0},
    {GnssSystem::QZSS, 'J', "QZSS", 10, 192},
    {GnssSystem::SBAS, 'S', "SBAS", 58, 100},      // PRN 120-158
    {GnssSystem::IRNSS, 'I', "IRNSS", 14, 0},
};

constexpr bool inEnumOrder() {
  for (int k = 0; k < kNumGnssSystems; ++k)
    if (static_cast<int>(kSystems[k].system) != k) return false;
  return true;
}
static_assert(inEnumOrder(), "kSystems is indexed by GnssSystem");

const SystemRow* rowOf(GnssSystem system) {
  const auto k = static_cast<std::size_t>(system);
  return k < static_cast<std::size_t>(kNumGnssSystems) ? &kSystems[k] : nullptr;
}

}  // namespace

char systemLetter(GnssSystem system) {
  const SystemRow* row = rowOf(system);
  return row != nullptr ? row->letter : '?';
}

std::optional<GnssSystem> systemFromLetter(char letter) {
  for (const auto& row : kSystems)
    if (row.letter == letter) return row.system;
  return std::nullopt;
}

std::string_view systemName(GnssSystem system) {
  const SystemRow* row = rowOf(system);
  return row != nullptr ? row->name : "unknown";
}

int SatelliteId::maxPrn(GnssSystem system) {
  const SystemRow* row = rowOf(system);
  return row != nullptr ? row->max_prn : 0;
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
  if (const int offset = rowOf(id.system)->full_prn_offset; offset > 0 && value > offset) value -= offset;
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
