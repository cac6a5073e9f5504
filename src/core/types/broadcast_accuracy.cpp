#include "ppp_bayes_tree/types/broadcast_accuracy.h"

#include <cmath>

namespace ppp {
namespace {

// IS-GPS-200 20.3.3.3.1.1: the nominal URA of each index 0..15 (index 15: no
// accuracy prediction, written as the next power of two, as RINEX writers do).
constexpr double kUraNominal_m[16] = {2.0,   2.8,   4.0,   5.7,    8.0,    11.3,   16.0,   32.0,
                                      64.0,  128.0, 256.0, 512.0,  1024.0, 2048.0, 4096.0, 8192.0};
// IS-GPS-200 20.3.3.3.1.3: the upper bound of each URA range, index 0..14.
constexpr double kUraRangeUpper_m[15] = {2.4,   3.4,   4.85,  6.85,   9.65,   13.65,  24.0,  48.0,
                                         96.0,  192.0, 384.0, 768.0,  1536.0, 3072.0, 6144.0};

}  // namespace

double gpsUra_m(int index) { return index >= 0 && index < 16 ? kUraNominal_m[index] : kUraNominal_m[15]; }

int gpsUraIndex(double ura_m) {
  for (int i = 0; i < 15; ++i)
    if (ura_m <= kUraRangeUpper_m[i]) return i;
  return 15;
}

std::optional<double> galileoSisa_m(int index) {
  if (index < 0) return std::nullopt;
  if (index < 50) return 0.01 * index;
  if (index < 75) return 0.5 + 0.02 * (index - 50);
  if (index < 100) return 1.0 + 0.04 * (index - 75);
  if (index < 126) return 2.0 + 0.16 * (index - 100);
  return std::nullopt;  // spare, 255: NAPA
}

int galileoSisaIndex(const std::optional<double>& sisa_m) {
  if (!sisa_m || !std::isfinite(*sisa_m) || *sisa_m < 0.0) return 255;
  const double s = *sisa_m;
  if (s < 0.5) return static_cast<int>(std::lround(s / 0.01));
  if (s < 1.0) return 50 + static_cast<int>(std::lround((s - 0.5) / 0.02));
  if (s < 2.0) return 75 + static_cast<int>(std::lround((s - 1.0) / 0.04));
  if (s <= 6.0) return 100 + static_cast<int>(std::lround((s - 2.0) / 0.16));
  return 255;
}

}  // namespace ppp
