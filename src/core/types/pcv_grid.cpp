#include "ppp_bayes_tree/types/pcv_grid.h"

#include <cmath>

#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

namespace {

/// Position of an angle on the zenith grid: node index and fraction towards
/// the next node. nullopt outside [ZEN1, ZEN2] (tolerance 1e-9 deg).
struct GridPosition {
  std::size_t node = 0;
  double fraction = 0.0;
};

std::optional<GridPosition> zenithPosition(const PcvGrid& grid, double zenith_rad) {
  const std::size_t n = grid.zenithCount();
  if (n == 0 || !std::isfinite(zenith_rad)) return std::nullopt;
  const double z_deg = zenith_rad * kRadToDeg;
  constexpr double kTolerance_deg = 1e-9;
  if (z_deg < grid.zenith_first_deg - kTolerance_deg || z_deg > grid.zenith_last_deg + kTolerance_deg) {
    return std::nullopt;
  }
  if (n == 1 || !(grid.zenith_step_deg > 0.0)) return GridPosition{0, 0.0};
  const double u = (z_deg - grid.zenith_first_deg) / grid.zenith_step_deg;
  if (u <= 0.0) return GridPosition{0, 0.0};
  const double last = static_cast<double>(n - 1);
  if (u >= last) return GridPosition{n - 2, 1.0};
  const auto node = static_cast<std::size_t>(std::floor(u));
  return GridPosition{node, u - static_cast<double>(node)};
}

double lerp(double a, double b, double t) { return a + (b - a) * t; }

}  // namespace

std::size_t PcvGrid::azimuthRowCount() const {
  const std::size_t n = zenithCount();
  return n == 0 ? 0 : azimuth_m.size() / n;
}

std::optional<double> PcvGrid::evaluateNoAzimuth_m(double zenith_rad) const {
  const auto p = zenithPosition(*this, zenith_rad);
  if (!p) return std::nullopt;
  if (zenithCount() == 1) return noazi_m[0];
  return lerp(noazi_m[p->node], noazi_m[p->node + 1], p->fraction);
}

std::optional<double> PcvGrid::evaluate_m(double zenith_rad, double azimuth_rad) const {
  if (!azimuthDependent()) return evaluateNoAzimuth_m(zenith_rad);
  const auto p = zenithPosition(*this, zenith_rad);
  if (!p || !std::isfinite(azimuth_rad)) return std::nullopt;
  const std::size_t rows = azimuthRowCount();
  if (rows < 2) return std::nullopt;
  // Azimuth wraps into [0, 360); the row at 360 deg closes the circle.
  double a_deg = std::fmod(azimuth_rad * kRadToDeg, 360.0);
  if (a_deg < 0.0) a_deg += 360.0;
  double v = a_deg / azimuth_step_deg;
  const double last_row = static_cast<double>(rows - 1);
  if (v > last_row) v = last_row;
  std::size_t row = static_cast<std::size_t>(std::floor(v));
  if (row >= rows - 1) row = rows - 2;
  const double ta = v - static_cast<double>(row);
  const std::size_t z1 = zenithCount() == 1 ? p->node : p->node + 1;
  const double at_row = lerp(node_m(row, p->node), node_m(row, z1), p->fraction);
  const double at_next = lerp(node_m(row + 1, p->node), node_m(row + 1, z1), p->fraction);
  return lerp(at_row, at_next, ta);
}

}  // namespace ppp
