#include "ppp_bayes_tree/navigation/imu_input_screen.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/types/number_text.h"

namespace ppp {

std::string imuInputProblemText(ImuInputProblem problem) {
  switch (problem) {
    case ImuInputProblem::NonFinite: return "non-finite value";
    case ImuInputProblem::TimeBackwards: return "time going backwards";
    case ImuInputProblem::DuplicateTime: return "duplicate time";
    case ImuInputProblem::Gap: return "gap";
    case ImuInputProblem::Saturated: return "saturated";
    case ImuInputProblem::InGravityUnits: return "accelerations in g, not m/s^2";
    case ImuInputProblem::FarFromGnssTime: return "far from the GNSS time";
  }
  return "unknown";
}

std::string imuAccelerationUnitsText(ImuAccelerationUnits units) {
  switch (units) {
    case ImuAccelerationUnits::Undecided: return "undecided";
    case ImuAccelerationUnits::MetresPerSecondSquared: return "m/s^2";
    case ImuAccelerationUnits::Gravity: return "g";
  }
  return "unknown";
}

namespace {

/// The largest |component| of a vector.
double largestAxis(const Eigen::Vector3d& v) { return v.cwiseAbs().maxCoeff(); }

}  // namespace

double meanSpecificForceMagnitude(const std::vector<ImuSample>& samples, std::size_t count) {
  const std::size_t n = std::min(count, samples.size());
  if (n == 0) return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += samples[i].specific_force_mps2.norm();
  return sum / static_cast<double>(n);
}

bool meanForceLooksLikeGravityUnits(double mean_specific_force) {
  return mean_specific_force >= 0.5 && mean_specific_force <= 2.0;
}

ImuInputScreen::ImuInputScreen(ImuInputScreenOptions options) : options_(std::move(options)) {
  if (!(options_.max_gap_s > 0.0)) throw std::invalid_argument("IMU screen: max_gap_s must be > 0");
  if (!(options_.saturation_fraction > 0.0 && options_.saturation_fraction <= 1.0))
    throw std::invalid_argument("IMU screen: saturation_fraction must be in (0, 1]");
  if (!(options_.max_gnss_offset_s > 0.0)) throw std::invalid_argument("IMU screen: max_gnss_offset_s must be > 0");
  if (options_.units_readings == 0) throw std::invalid_argument("IMU screen: units_readings must be > 0");
}

std::size_t ImuInputScreen::count(ImuInputProblem problem) const {
  const auto it = problems_.find(problem);
  return it == problems_.end() ? 0 : it->second.count;
}

void ImuInputScreen::note(ImuInputProblem problem, const ImuSample& reading, const std::string& detail) {
  ImuProblemCount& c = problems_[problem];
  if (c.count++ == 0)
    c.first = "reading at " + reading.time.toString(TimeSystem::GPS, 3) + ": " + imuInputProblemText(problem) +
              (detail.empty() ? "" : " (" + detail + ")");
}

std::optional<ImuInputProblem> ImuInputScreen::refusal(const ImuSample& reading,
                                                       const std::optional<GnssTime>& gnss_time) {
  if (!reading.specific_force_mps2.allFinite() || !reading.angular_rate_radps.allFinite())
    return ImuInputProblem::NonFinite;
  // Another time base first: its stamps would also read as going backwards.
  if (gnss_time && std::abs(reading.time - *gnss_time) > options_.max_gnss_offset_s)
    return ImuInputProblem::FarFromGnssTime;
  if (last_time_ && options_.check_time_order) {
    const double dt = reading.time - *last_time_;
    if (dt < 0.0) return ImuInputProblem::TimeBackwards;
    if (dt == 0.0) return ImuInputProblem::DuplicateTime;
  }
  const double scale = options_.saturation_fraction;
  if ((options_.accel_full_scale_mps2 &&
       largestAxis(reading.specific_force_mps2) >= scale * *options_.accel_full_scale_mps2) ||
      (options_.gyro_full_scale_radps &&
       largestAxis(reading.angular_rate_radps) >= scale * *options_.gyro_full_scale_radps))
    return ImuInputProblem::Saturated;
  if (options_.check_time_order && last_time_ && reading.time - *last_time_ > options_.max_gap_s)
    note(ImuInputProblem::Gap, reading, fixedDecimals(reading.time - *last_time_, 3) + " s since the previous reading");
  last_time_ = reading.time;
  return std::nullopt;
}

std::vector<ImuSample> ImuInputScreen::decideUnits() {
  if (held_.empty()) return {};
  const double mean = meanSpecificForceMagnitude(held_, held_.size());
  std::vector<ImuSample> released;
  if (meanForceLooksLikeGravityUnits(mean)) {
    units_ = ImuAccelerationUnits::Gravity;
    for (const ImuSample& s : held_)
      note(ImuInputProblem::InGravityUnits, s,
           "mean specific force " + fixedDecimals(mean, 3) + " over the first " + std::to_string(held_.size()) +
               " readings; at rest it is " + fixedDecimals(kStandardGravity_mps2, 2) + " m/s^2");
  } else {
    units_ = ImuAccelerationUnits::MetresPerSecondSquared;
    released.swap(held_);
    accepted_ += released.size();
  }
  held_.clear();
  return released;
}

std::vector<ImuSample> ImuInputScreen::push(const ImuSample& reading, const std::optional<GnssTime>& gnss_time) {
  if (const auto problem = refusal(reading, gnss_time)) {
    note(*problem, reading, "");
    return {};
  }
  switch (units_) {
    case ImuAccelerationUnits::Gravity:
      note(ImuInputProblem::InGravityUnits, reading, "");
      return {};
    case ImuAccelerationUnits::MetresPerSecondSquared:
      ++accepted_;
      return {reading};
    case ImuAccelerationUnits::Undecided:
      held_.push_back(reading);
      return held_.size() >= options_.units_readings ? decideUnits() : std::vector<ImuSample>{};
  }
  return {};
}

std::vector<ImuSample> ImuInputScreen::finish() { return decideUnits(); }

std::string ImuInputScreen::summary() const {
  std::size_t refused = 0;
  std::string parts;
  for (const auto& [problem, c] : problems_) {
    if (problem == ImuInputProblem::Gap) continue;
    refused += c.count;
    parts += (parts.empty() ? "" : ", ") + std::to_string(c.count) + " " + imuInputProblemText(problem);
  }
  std::string out = std::to_string(accepted_) + " IMU readings accepted; " + std::to_string(refused) + " refused";
  if (!parts.empty()) out += " (" + parts + ")";
  return out + "; " + std::to_string(count(ImuInputProblem::Gap)) + " gaps; units " +
         imuAccelerationUnitsText(units_);
}

}  // namespace ppp
