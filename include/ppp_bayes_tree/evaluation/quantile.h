#pragma once
// Quantiles of a sample by rank, for the figures of the live nodes' diagnostics and
// of the benchmarks: the value at 0-based index floor(p n) of the n sorted values
// (the last for p = 1; p = 0.5 of an even count is the upper of the two middle ones).
#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace ppp {

/// The p-quantile (p in 0..1) of `sorted` (ascending); NaN when empty.
inline double quantileOfSorted(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return std::numeric_limits<double>::quiet_NaN();
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(p * static_cast<double>(sorted.size())))];
}

/// The p-quantile (p in 0..1) of `values` in any order (sorts a copy); NaN when empty.
inline double quantile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  return quantileOfSorted(values, p);
}

}  // namespace ppp
