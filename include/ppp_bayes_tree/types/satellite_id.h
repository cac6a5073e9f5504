#pragma once
// Satellite identifiers: constellation letter plus PRN/slot number, as in RINEX 3
// ("G05", "R21", "E11", "C23", "J02").
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace ppp {

enum class GnssSystem : std::uint8_t { GPS, GLONASS, Galileo, BeiDou, QZSS, SBAS, IRNSS };
constexpr int kNumGnssSystems = 7;

/// RINEX system letter: G R E C J S I.
char systemLetter(GnssSystem system);
std::optional<GnssSystem> systemFromLetter(char letter);
std::string_view systemName(GnssSystem system);

struct SatelliteId {
  GnssSystem system = GnssSystem::GPS;
  int prn = 0;  // PRN (GPS, Galileo, BeiDou), slot (GLONASS), PRN-100 (SBAS), PRN-192 (QZSS)

  /// Parses "G05", "G 5", "G5"; a blank system letter means GPS (RINEX 2).
  /// nullopt on anything else, or a number outside the system's range.
  static std::optional<SatelliteId> parse(std::string_view text);
  /// Largest valid number for the system (GPS 32... we allow up to 99 for future PRNs).
  static int maxPrn(GnssSystem system);

  std::string toString() const;  // "G05"

  friend bool operator==(const SatelliteId& a, const SatelliteId& b) {
    return a.system == b.system && a.prn == b.prn;
  }
  friend bool operator!=(const SatelliteId& a, const SatelliteId& b) { return !(a == b); }
  friend bool operator<(const SatelliteId& a, const SatelliteId& b) {
    return a.system != b.system ? a.system < b.system : a.prn < b.prn;
  }
  /// Dense index 0..(kNumGnssSystems*100-1) for array-based lookup tables.
  int index() const { return static_cast<int>(system) * 100 + prn; }
};

}  // namespace ppp

template <>
struct std::hash<ppp::SatelliteId> {
  std::size_t operator()(const ppp::SatelliteId& s) const noexcept {
    return static_cast<std::size_t>(s.index());
  }
};
