#include "ppp_bayes_tree/types/ssr_corrections.h"

#include <array>
#include <cmath>

namespace ppp {

std::string_view ssrMessageKindName(SsrMessageKind kind) {
  switch (kind) {
    case SsrMessageKind::Orbit: return "orbit";
    case SsrMessageKind::Clock: return "clock";
    case SsrMessageKind::Combined: return "orbit+clock";
    case SsrMessageKind::CodeBias: return "code bias";
    case SsrMessageKind::PhaseBias: return "phase bias";
    case SsrMessageKind::Ura: return "URA";
    case SsrMessageKind::HighRateClock: return "high-rate clock";
    case SsrMessageKind::Vtec: return "VTEC";
  }
  return "?";
}

namespace {
constexpr std::array<double, 16> kUpdateIntervals_s = {1, 2, 5, 10, 15, 30, 60, 120,
                                                       240, 300, 600, 900, 1800, 3600, 7200, 10800};

// Signal id -> two-character RINEX signal ("" = reserved).
// RTCM 10403.3 SSR tables (3.5-91 GPS, 3.5-93 GLONASS, 3.5-96 Galileo,
// 3.5-99 QZSS, 3.5-102 SBAS, 3.5-105 BeiDou).
constexpr std::array<const char*, 32> kRtcmGps = {"1C", "1P", "1W", "", "", "2C", "2D", "2S", "2L", "2X", "2P",
                                                  "2W", "", "", "5I", "5Q", "5X", "1S", "1L", "1X"};
constexpr std::array<const char*, 32> kRtcmGlo = {"1C", "1P", "2C", "2P"};
constexpr std::array<const char*, 32> kRtcmGal = {"1A", "1B", "1C", "1X", "1Z", "5I", "5Q", "5X", "7I", "7Q",
                                                  "7X", "8I", "8Q", "8X", "6A", "6B", "6C", "6X", "6Z"};
constexpr std::array<const char*, 32> kRtcmQzs = {"1C", "1S", "1L", "2S", "2L", "2X", "5I",
                                                  "5Q", "5X", "6S", "6L", "6X", "1X"};
constexpr std::array<const char*, 32> kRtcmSbs = {"1C", "5I", "5Q", "5X"};
// BeiDou ids 9-14 (B1C, B2a) as the IGS real-time streams send them.
constexpr std::array<const char*, 32> kRtcmBds = {"2I", "2Q", "2X", "6I", "6Q", "6X", "7I", "7Q",
                                                  "7X", "1D", "1P", "1X", "5D", "5P", "5X"};
// IGS-SSR v1.00, section 7 (signal and tracking mode identifiers).
constexpr std::array<const char*, 32> kIgsGps = {"1C", "1P", "1W", "1S", "1L", "2C", "2D", "2S",
                                                 "2L", "2X", "2P", "2W", "", "", "5I", "5Q"};
constexpr std::array<const char*, 32> kIgsGlo = {"1C", "1P", "2C", "2P", "4A", "4B", "6A", "6B", "3I", "3Q"};
constexpr std::array<const char*, 32> kIgsGal = {"1A", "1B", "1C", "", "", "5I", "5Q", "", "7I",
                                                 "7Q", "", "8I", "8Q", "", "6A", "6B", "6C"};
constexpr std::array<const char*, 32> kIgsQzs = {"1C", "1S", "1L", "2S", "2L", "", "5I", "5Q", "",
                                                 "6S", "6L", "", "", "", "", "", "", "6E"};
constexpr std::array<const char*, 32> kIgsBds = {"2I", "2Q", "", "6I", "6Q", "", "7I", "7Q", "",  "1D",
                                                 "1P", "", "5D", "5P", "", "1A", "", "", "6A"};
constexpr std::array<const char*, 32> kIgsSbs = {"1C", "5I", "5Q"};

/// Signal id tables per system: RTCM 10403.3 and IGS-SSR v1.00 (above).
struct SsrSignalRow {
  GnssSystem system;
  const std::array<const char*, 32>* rtcm;
  const std::array<const char*, 32>* igs;
};
constexpr SsrSignalRow kSignalTables[] = {
    {GnssSystem::GPS, &kRtcmGps, &kIgsGps},     {GnssSystem::GLONASS, &kRtcmGlo, &kIgsGlo},
    {GnssSystem::Galileo, &kRtcmGal, &kIgsGal}, {GnssSystem::QZSS, &kRtcmQzs, &kIgsQzs},
    {GnssSystem::SBAS, &kRtcmSbs, &kIgsSbs},    {GnssSystem::BeiDou, &kRtcmBds, &kIgsBds},
};

const std::array<const char*, 32>& table(GnssSystem system, bool igs) {
  static constexpr std::array<const char*, 32> kNone{};
  for (const auto& row : kSignalTables)
    if (row.system == system) return igs ? *row.igs : *row.rtcm;
  return kNone;
}
}  // namespace

double ssrUpdateInterval_s(int code) {
  return (code >= 0 && code < 16) ? kUpdateIntervals_s[static_cast<std::size_t>(code)] : 1.0;
}

std::optional<int> ssrUpdateIntervalCode(double interval_s) {
  for (std::size_t i = 0; i < kUpdateIntervals_s.size(); ++i)
    if (std::abs(kUpdateIntervals_s[i] - interval_s) < 1e-9) return static_cast<int>(i);
  return std::nullopt;
}

std::optional<ObservationCode> ssrSignalCode(GnssSystem system, int signal_id, bool igs_ssr) {
  if (signal_id < 0 || signal_id >= 32) return std::nullopt;
  const char* s = table(system, igs_ssr)[static_cast<std::size_t>(signal_id)];
  if (s == nullptr || s[0] == '\0') return std::nullopt;
  ObservationCode code;
  code.type = ObservableType::Pseudorange;
  code.band = s[0];
  code.attribute = s[1];
  return code;
}

std::optional<int> ssrSignalId(GnssSystem system, const ObservationCode& code, bool igs_ssr) {
  const auto& t = table(system, igs_ssr);
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] != nullptr && t[i][0] == code.band && t[i][1] == code.attribute) return static_cast<int>(i);
  return std::nullopt;
}

}  // namespace ppp
