#include "ppp_bayes_tree/models/product_sanity.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// Position known in ECEF at t_k, expressed in the non-rotating frame aligned with
/// ECEF at t_ref: the ECEF frame turns by omega (t_ref - t_k) in between.
Eigen::Vector3d inFrameOf(const Eigen::Vector3d& x_ecef_m, double t_ref_minus_tk_s) {
  return Eigen::AngleAxisd(-kEarthRotationRate_radps * t_ref_minus_tk_s, Eigen::Vector3d::UnitZ()) * x_ecef_m;
}

/// Lagrange interpolation at x of values at abscissae tau (scaled, centred).
Eigen::Vector3d lagrange(const std::vector<double>& tau, const std::vector<Eigen::Vector3d>& values, double x) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < tau.size(); ++j) {
    double w = 1.0;
    for (std::size_t m = 0; m < tau.size(); ++m)
      if (m != j) w *= (x - tau[m]) / (tau[j] - tau[m]);
    sum += w * values[j];
  }
  return sum;
}

/// Indices of the `count` usable nodes nearest in time to node i (i itself
/// excluded), walking outwards on each side until a spacing above
/// max_spacing_s; sorted by time.
template <class Usable>
std::vector<std::size_t> nearestNodes(const std::vector<GnssTime>& times, std::size_t i, int count,
                                      double max_spacing_s, const Usable& usable) {
  const auto side = [&](int step) {
    std::vector<std::size_t> found;
    GnssTime edge = times[i];
    for (long k = static_cast<long>(i) + step; k >= 0 && k < static_cast<long>(times.size()) &&
                                               static_cast<int>(found.size()) < count;
         k += step) {
      const auto u = static_cast<std::size_t>(k);
      if (std::abs(times[u] - edge) > max_spacing_s) break;
      if (!usable(u)) continue;
      found.push_back(u);
      edge = times[u];
    }
    return found;
  };
  const std::vector<std::size_t> left = side(-1), right = side(+1);
  std::vector<std::size_t> out;
  std::size_t l = 0, r = 0;
  while (static_cast<int>(out.size()) < count && (l < left.size() || r < right.size())) {
    const bool take_left =
        r >= right.size() || (l < left.size() && times[i] - times[left[l]] <= times[right[r]] - times[i]);
    out.push_back(take_left ? left[l++] : right[r++]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::string OrbitOutlier::describe() const {
  return satellite.toString() + " orbit at " + time.toString(TimeSystem::GPS, 0) + ": leave-one-out miss " +
         format("%.3f", miss_m) + " m > " + format("%.3f", threshold_m) + " m (a single bad SP3 value)";
}

std::string ClockOutlier::describe() const {
  return satellite.toString() + " clock at " + time.toString(TimeSystem::GPS, 0) + ": leave-one-out miss " +
         format("%.3f", miss_s * 1e9) + " ns > " + format("%.3f", threshold_s * 1e9) +
         " ns (a clock spike or jump)";
}

namespace {

/// Leave-one-out miss of node i and the threshold that applies to it; nullopt
/// when the node is not judged (too few nodes, or an extrapolation).
template <class Usable>
std::optional<OrbitOutlier> orbitMiss(const SatelliteId& sat, const std::vector<Sp3Record>& records,
                                      const std::vector<GnssTime>& times, std::size_t i, const Usable& usable,
                                      const OrbitCheckOptions& options) {
  const int window = std::max(3, options.window_nodes);
  const std::vector<std::size_t> nodes = nearestNodes(times, i, window, options.max_spacing_s, usable);
  if (static_cast<int>(nodes.size()) < window) return std::nullopt;
  const auto before = static_cast<int>(std::count_if(nodes.begin(), nodes.end(), [i](std::size_t k) { return k < i; }));
  const int after = static_cast<int>(nodes.size()) - before;
  if (before == 0 || after == 0) return std::nullopt;  // an extrapolation: not judged
  const bool balanced = std::min(before, after) >= window / 2 - 1;
  const double scale_s = std::max(1.0, times[nodes.back()] - times[nodes.front()]);
  std::vector<double> tau;
  std::vector<Eigen::Vector3d> values;
  for (std::size_t k : nodes) {
    tau.push_back((times[k] - times[i]) / scale_s);
    values.push_back(inFrameOf(*records[k].position_ecef_m, times[i] - times[k]));
  }
  const double miss = (lagrange(tau, values, 0.0) - *records[i].position_ecef_m).norm();
  return OrbitOutlier{sat, times[i], miss, balanced ? options.threshold_m : options.edge_threshold_m};
}

std::vector<GnssTime> timesOf(const std::vector<Sp3Record>& records) {
  std::vector<GnssTime> times;
  for (const auto& r : records) times.push_back(r.time);
  return times;
}

bool hasPosition(const Sp3Record& r) { return r.position_ecef_m && !r.position_marked_bad; }

std::size_t indexOf(const std::vector<GnssTime>& times, const GnssTime& t) {
  return static_cast<std::size_t>(std::lower_bound(times.begin(), times.end(), t) - times.begin());
}

/// Candidates tried per removal (the worst ratios).
constexpr std::size_t kMaxCandidates = 6;

/// Eccentricity of the orbit from the extreme radii of its nodes:
/// (r_max - r_min) / (r_max + r_min).
double eccentricityOf(const std::vector<Sp3Record>& records) {
  double r_min = std::numeric_limits<double>::infinity(), r_max = 0.0;
  for (const auto& r : records)
    if (hasPosition(r)) {
      r_min = std::min(r_min, r.position_ecef_m->norm());
      r_max = std::max(r_max, r.position_ecef_m->norm());
    }
  return r_max > r_min ? (r_max - r_min) / (r_max + r_min) : 0.0;
}

/// One pass over a satellite: every judged node's miss, the thresholds scaled for
/// an eccentric orbit.
template <class Usable>
std::vector<OrbitOutlier> satelliteMisses(const SatelliteId& sat, const std::vector<Sp3Record>& records,
                                          const std::vector<GnssTime>& times, const Usable& usable,
                                          const OrbitCheckOptions& options) {
  const double scale = eccentricityOf(records) > options.eccentricity_limit ? options.eccentric_orbit_factor : 1.0;
  std::vector<OrbitOutlier> misses;
  for (std::size_t i = 0; i < records.size(); ++i)
    if (usable(i))
      if (auto m = orbitMiss(sat, records, times, i, usable, options)) {
        m->threshold_m *= scale;
        misses.push_back(*m);
      }
  return misses;
}

}  // namespace

std::vector<OrbitOutlier> orbitLeaveOneOutMisses(const Sp3File& file, const OrbitCheckOptions& options) {
  std::vector<OrbitOutlier> out;
  for (const auto& entry : file.satellites) {  // named: lambdas below capture them
    const SatelliteId& sat = entry.first;
    const std::vector<Sp3Record>& records = entry.second;
    const std::vector<GnssTime> times = timesOf(records);
    const auto usable = [&](std::size_t k) { return hasPosition(records[k]); };
    const std::vector<OrbitOutlier> misses = satelliteMisses(sat, records, times, usable, options);
    out.insert(out.end(), misses.begin(), misses.end());
  }
  return out;
}

std::vector<OrbitOutlier> findOrbitOutliers(const Sp3File& file, const OrbitCheckOptions& options) {
  std::vector<OrbitOutlier> out;
  for (const auto& entry : file.satellites) {  // named: lambdas below capture them
    const SatelliteId& sat = entry.first;
    const std::vector<Sp3Record>& records = entry.second;
    const std::vector<GnssTime> times = timesOf(records);
    std::vector<bool> removed(records.size(), false);
    const auto usable = [&](std::size_t k) { return !removed[k] && hasPosition(records[k]); };
    const auto worstRatio = [](const std::vector<OrbitOutlier>& misses) {
      double worst = 0.0;
      for (const auto& m : misses) worst = std::max(worst, m.miss_m / m.threshold_m);
      return worst;
    };
    for (;;) {
      // Nodes over their threshold are candidates; a bad node also spoils the
      // predictions of its neighbours (near the ends by several times its own
      // error), so the culprit is the candidate whose removal leaves the others
      // most consistent, not the largest miss.
      const std::vector<OrbitOutlier> misses = satelliteMisses(sat, records, times, usable, options);
      std::vector<OrbitOutlier> candidates;
      for (const auto& m : misses)
        if (m.miss_m > m.threshold_m) candidates.push_back(m);
      if (candidates.empty()) break;
      std::sort(candidates.begin(), candidates.end(),
                [](const auto& a, const auto& b) { return a.miss_m / a.threshold_m > b.miss_m / b.threshold_m; });
      if (candidates.size() > kMaxCandidates) candidates.resize(kMaxCandidates);
      std::size_t best = 0;
      double best_rest = std::numeric_limits<double>::infinity();
      for (std::size_t c = 0; c < candidates.size(); ++c) {
        const std::size_t index = indexOf(times, candidates[c].time);
        removed[index] = true;
        const double rest = worstRatio(satelliteMisses(sat, records, times, usable, options));
        removed[index] = false;
        if (rest < best_rest) {
          best_rest = rest;
          best = c;
        }
      }
      removed[indexOf(times, candidates[best].time)] = true;
      out.push_back(candidates[best]);
    }
  }
  return out;
}

void markOrbitOutliers(Sp3File& file, const std::vector<OrbitOutlier>& outliers) {
  for (const auto& o : outliers) {
    auto it = file.satellites.find(o.satellite);
    if (it == file.satellites.end()) continue;
    for (auto& r : it->second) {
      if (r.time != o.time) continue;
      r.position_ecef_m.reset();
      r.velocity_ecef_mps.reset();
      r.position_marked_bad = true;
    }
  }
}

std::vector<ClockOutlier> findClockOutliers(const RinexClockFile& file, const ClockCheckOptions& options) {
  // Signed leave-one-out miss (record - prediction) of every interior record.
  struct Miss {
    std::size_t index = 0;
    double miss_s = 0.0;
  };
  std::map<SatelliteId, std::vector<Miss>> misses;
  std::map<GnssTime, std::vector<double>> by_epoch;
  for (const auto& entry : file.satellite_clocks) {
    const SatelliteId& sat = entry.first;
    const std::vector<ClockRecord>& records = entry.second;
    std::vector<GnssTime> times;
    for (const auto& r : records) times.push_back(r.time);
    const auto usable = [](std::size_t) { return true; };
    for (std::size_t i = 0; i < records.size(); ++i) {
      const std::vector<std::size_t> nodes = nearestNodes(times, i, 4, options.max_spacing_s, usable);
      if (nodes.size() < 4 || !(nodes.front() < i && nodes.back() > i)) continue;  // interior records only
      // Least-squares line through the neighbours, evaluated at t_i (values relative to record i).
      double sw = 0, st = 0, sy = 0, stt = 0, sty = 0;
      for (std::size_t k : nodes) {
        const double t = times[k] - times[i];
        const double y = records[k].clock_bias_s - records[i].clock_bias_s;
        sw += 1; st += t; sy += y; stt += t * t; sty += t * y;
      }
      const double det = sw * stt - st * st;
      if (!(std::abs(det) > 0.0)) continue;
      const double miss_s = -(stt * sy - st * sty) / det;  // record minus prediction
      misses[sat].push_back({i, miss_s});
      by_epoch[times[i]].push_back(miss_s);
    }
  }
  // The epoch-common part (a jump of the products' clock datum, shared by every
  // satellite and absorbed by the receiver clock) is not a satellite's error.
  std::map<GnssTime, double> common_s;
  for (auto& [t, v] : by_epoch) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    common_s[t] = v.size() >= 3 ? v[v.size() / 2] : 0.0;
  }
  // A wrong value spoils its neighbours' predictions by a quarter of its error:
  // an outlier is over the threshold and the largest within two records.
  std::vector<ClockOutlier> out;
  for (const auto& entry : misses) {
    const SatelliteId& sat = entry.first;
    const auto& list = entry.second;
    const auto& records = file.satellite_clocks.at(sat);
    const auto own = [&](std::size_t k) { return std::abs(list[k].miss_s - common_s[records[list[k].index].time]); };
    for (std::size_t k = 0; k < list.size(); ++k) {
      const double m = own(k);
      if (m <= options.threshold_s) continue;
      bool largest = true;
      for (std::size_t j = k >= 2 ? k - 2 : 0; j < std::min(list.size(), k + 3); ++j)
        if (j != k && own(j) > m) largest = false;
      if (largest) out.push_back({sat, records[list[k].index].time, m, options.threshold_s});
    }
  }
  return out;
}

void markClockOutliers(RinexClockFile& file, const std::vector<ClockOutlier>& outliers) {
  for (const auto& o : outliers) {
    auto it = file.satellite_clocks.find(o.satellite);
    if (it == file.satellite_clocks.end()) continue;
    auto& v = it->second;
    v.erase(std::remove_if(v.begin(), v.end(), [&](const ClockRecord& r) { return r.time == o.time; }), v.end());
  }
}

}  // namespace ppp
