#include "ppp_bayes_tree/ros/imu_epoch_hold.h"

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp_ros {

std::string imuWaitOutcomeText(ImuWaitOutcome outcome) {
  switch (outcome) {
    case ImuWaitOutcome::Wait: return "wait";
    case ImuWaitOutcome::Covered: return "covered";
    case ImuWaitOutcome::ImuSilent: return "IMU silent";
    case ImuWaitOutcome::WaitedOut: return "waited out";
    case ImuWaitOutcome::NoWait: return "no wait";
    case ImuWaitOutcome::ClockStopped: return "clock stopped";
  }
  return "unknown";
}

ImuWaitDecision decideImuWait(const ppp::GnssTime& epoch_time, double ready_s, double now_s, const ImuProgress& imu,
                              double max_wait_s) {
  ImuWaitDecision d;
  if (imu.newest_reading) d.imu_lag_s = epoch_time - *imu.newest_reading;
  if (!(max_wait_s > 0.0)) {
    d.outcome = ImuWaitOutcome::NoWait;
  } else if (d.imu_lag_s && *d.imu_lag_s <= 0.0) {
    d.outcome = ImuWaitOutcome::Covered;
  } else if (!imu.newest_reading || !imu.newest_arrival_s || ready_s - *imu.newest_arrival_s > max_wait_s) {
    d.outcome = ImuWaitOutcome::ImuSilent;
  } else if (now_s - ready_s >= max_wait_s) {
    d.outcome = ImuWaitOutcome::WaitedOut;
  }
  return d;
}

std::string imuWaitedOutText(const ppp::GnssTime& epoch_time, double waited_s, const ImuWaitDecision& decision,
                             const std::string& topic, double max_wait_s) {
  const std::string lag = decision.imu_lag_s ? ppp::format("%.1f ms before the epoch", *decision.imu_lag_s * 1e3) : "none";
  const std::string clock = decision.outcome == ImuWaitOutcome::ClockStopped
                                ? " of steady time, the ROS clock standing still (a bag's /clock stopped),"
                                : "";
  return "epoch " + epoch_time.toString(ppp::TimeSystem::GPS, 3) + " processed after waiting " +
         ppp::format("%.3f s", waited_s) + clock + " for the IMU on " + topic + " (ros.imu.max_wait_s " +
         ppp::format("%g", max_wait_s) + "): its newest reading " + lag + ", the readings after it missing (counted)";
}

}  // namespace ppp_ros
