#include "ppp_bayes_tree/evaluation/ins_coast_from_truth.h"

#include <algorithm>

#include "ppp_bayes_tree/navigation/imu_coverage.h"
#include "ppp_bayes_tree/navigation/ins_mechanization.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

/// Index of the last reading at or before t; the size when there is none.
std::size_t readingHeldAt(const std::vector<ImuSample>& samples, const GnssTime& t) {
  const auto after = std::upper_bound(samples.begin(), samples.end(), t,
                                      [](const GnssTime& time, const ImuSample& s) { return time - s.time < 0.0; });
  return after == samples.begin() ? samples.size() : static_cast<std::size_t>(after - samples.begin()) - 1;
}

}  // namespace

std::optional<Eigen::Vector3d> insCoastErrorFromTruth_enu_m(const SimulatedImu& imu, const TrajectorySample& from,
                                                            const TrajectorySample& to, double max_hold_s) {
  // 1. The readings that hold within [from, to]: the one held at `from`, then each up to `to`.
  if (!(to.time - from.time > 0.0) || imu.samples.size() != imu.biases.size()) return std::nullopt;
  const std::size_t first = readingHeldAt(imu.samples, from.time);
  if (first == imu.samples.size()) return std::nullopt;
  std::size_t last = readingHeldAt(imu.samples, to.time);
  if (last > first && !(to.time - imu.samples[last].time > 0.0)) --last;  // a reading at `to` holds after it
  const std::vector<ImuSample> held(imu.samples.begin() + static_cast<std::ptrdiff_t>(first),
                                    imu.samples.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  if (!imuCoverage(held, from.time, to.time, max_hold_s).covered()) return std::nullopt;
  // 2. The coast from the true state with the true bias of the reading held at `from`.
  const ImuBias& bias = imu.biases[first];
  NavState state = trueNavState(from);
  GnssTime t = from.time;
  for (std::size_t k = 0; k < held.size(); ++k) {
    const GnssTime end = k + 1 < held.size() ? held[k + 1].time : to.time;
    state = ecefInsStep(state, held[k].specific_force_mps2 - bias.accel_mps2,
                        held[k].angular_rate_radps - bias.gyro_radps, end - t);
    t = end;
  }
  // 3. Against the truth at `to`.
  return ecefToEnu(state.position_world_m, to.position_ecef_m);
}

}  // namespace ppp
