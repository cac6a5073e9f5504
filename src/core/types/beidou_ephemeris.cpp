#include "ppp_bayes_tree/types/beidou_ephemeris.h"

#include <cmath>

namespace ppp {

double beidouUra_m(int index) {
  if (index < 0 || index >= 15) return 8192.0;
  if (index <= 6) return std::pow(2.0, 1.0 + 0.5 * index);
  return std::pow(2.0, index - 2.0);
}

int beidouUraIndex(double ura_m) {
  int best = 15;
  double best_distance = INFINITY;
  for (int n = 0; n < 16; ++n) {
    const double d = std::fabs(std::log(beidouUra_m(n)) - std::log(std::fmax(ura_m, 1e-3)));
    if (d < best_distance) {
      best_distance = d;
      best = n;
    }
  }
  return best;
}

}  // namespace ppp
