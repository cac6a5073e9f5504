#pragma once
// ImuEpochHold: the GNSS epochs of a GNSS/INS node (ppp_node.h with ekf_ins or
// smoother_ins) held until the IMU readings up to their time have arrived. An epoch
// takes the readings up to its time (NodeImuInput::takeUpTo); readings that arrive
// after it was processed are older than it: the filter skips them (it has held the
// last reading over the missing end of the interval), and a missing end longer than
// its max_imu_interval_s stops the INS (NoImuReadings: the node falls back to GNSS
// only). Transports and drivers deliver IMU and GNSS with different latencies (an
// IMU driver slower than the GNSS one, a bag's interleaving, Nagle's algorithm), so
// an epoch waits (as robot_localization's filter nodes queue their measurements and
// take each in time order after the prediction up to its stamp):
//   - until a reading at or after its time has been accepted (the readings before
//     it are then all there: the IMU topic is in time order, the screen refuses
//     readings going back), or
//   - at most ros.imu.max_wait_s after it became ready (then processed with the
//     readings there are; counted, with how far the IMU lagged), or, when the ROS
//     clock stands still (under /use_sim_time a bag's /clock stopped or paused: the ROS
//     deadline never comes), max_wait_s of steady time after it became ready and after
//     the ROS clock last moved (counted and warned as waited out, "clock stopped"), so
//     that no epoch stays held for ever, and
//   - not at all while the IMU is silent: no reading accepted yet (before the first
//     message, the extrinsics missing, an estimator reset) or none accepted for
//     longer than max_wait_s before the epoch became ready (the IMU stopped: the
//     node's fall-back to GNSS only is not delayed epoch after epoch).
// The epochs leave in the order they came (time order: the correction gate and the
// live input release them so), so one status per epoch and outputs in time order hold.
// The IMU's progress (its newest accepted reading and when it arrived) is the IMU
// input's (NodeImuInput::progress, node_imu_input.h), handed in at each release.
// ROS-free: times come in as arguments (ROS time in seconds for arrivals, GPST for data,
// HoldClock for the hold's calls).
#include <algorithm>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <utility>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp_ros {

/// What becomes of a held epoch.
enum class ImuWaitOutcome {
  Wait,       ///< the readings up to its time may still come: held
  Covered,    ///< a reading at or after its time has been accepted
  ImuSilent,  ///< no reading accepted yet, or none for longer than max_wait_s when it became ready
  WaitedOut,  ///< held max_wait_s without a reading at or after its time: processed with those there are
  NoWait,     ///< max_wait_s 0, or the estimator takes no readings (GNSS only): not held
  /// Held max_wait_s of steady time while the ROS clock stood still (a bag's /clock
  /// stopped), without a reading at or after its time: processed with those there are.
  ClockStopped,
};
/// "wait", "covered", "IMU silent", "waited out", "no wait", "clock stopped".
std::string imuWaitOutcomeText(ImuWaitOutcome outcome);

/// The IMU input as the hold sees it: its newest accepted reading and when it arrived
/// (NodeImuInput::progress); empty while no reading has been accepted.
struct ImuProgress {
  std::optional<ppp::GnssTime> newest_reading;  ///< data time (GPST)
  std::optional<double> newest_arrival_s;       ///< ROS time of its arrival [s]
};

/// The decision for one held epoch, with how far the IMU was behind it.
struct ImuWaitDecision {
  ImuWaitOutcome outcome = ImuWaitOutcome::Wait;
  /// Epoch time minus the newest accepted reading [s] (> 0: readings missing at the
  /// epoch's end); nullopt without a reading.
  std::optional<double> imu_lag_s;
};

/// The decision for an epoch of `epoch_time` ready since `ready_s` (ROS time [s]), at
/// `now_s`, given the IMU's progress and ros.imu.max_wait_s (0: never held).
ImuWaitDecision decideImuWait(const ppp::GnssTime& epoch_time, double ready_s, double now_s,
                              const ImuProgress& imu, double max_wait_s);

/// The time of a call to the hold: ROS time (the wait's clock; simulated under
/// /use_sim_time) and a steady clock's (the fallback when the ROS clock stands still) [s].
struct HoldClock {
  double ros_s = 0.0;
  double steady_s = 0.0;
};

/// The hold's counts since the start.
struct ImuWaitCounters {
  std::size_t held = 0;        ///< epochs that had to wait (not covered when they became ready)
  std::size_t covered = 0;     ///< of them released by a reading at or after their time
  std::size_t waited_out = 0;  ///< of them released by max_wait_s, readings missing at their end
  std::size_t clock_stopped = 0;  ///< of waited_out, by the steady clock while the ROS clock stood still
  std::size_t silent = 0;      ///< epochs not held because the IMU was silent
  double largest_lag_s = 0.0;  ///< the largest IMU lag of an epoch waited out [s]
  double longest_wait_s = 0.0; ///< the longest wait of an epoch [s]
};

/// One epoch leaving the hold.
template <class Epoch>
struct ReleasedEpoch {
  Epoch epoch;
  ppp::GnssTime time;
  ImuWaitDecision decision;
  /// now - ready [s]: ROS time; steady time when released as ClockStopped (the ROS clock stood still).
  double waited_s = 0.0;
};

/// The FIFO of epochs waiting for the IMU (`Epoch`: what the node processes later).
template <class Epoch>
class ImuEpochHold {
 public:
  explicit ImuEpochHold(double max_wait_s = 0.0) : max_wait_s_(max_wait_s) {}

  /// An epoch ready `now`, after those held (time order).
  void hold(Epoch epoch, const ppp::GnssTime& time, const HoldClock& now) {
    observeClock(now);
    held_.push_back({std::move(epoch), time, now.ros_s, now.steady_s});
  }
  /// The oldest held epoch when it may go on `now` given the IMU's progress `imu`,
  /// counted; nullopt while it waits. `waiting` false (the estimator takes no readings
  /// now): every held epoch goes on.
  std::optional<ReleasedEpoch<Epoch>> release(const HoldClock& now, const ImuProgress& imu, bool waiting = true) {
    observeClock(now);
    if (held_.empty()) return std::nullopt;
    Held& front = held_.front();
    ImuWaitDecision d = waiting ? decideImuWait(front.time, front.ready_s, now.ros_s, imu, max_wait_s_)
                                : ImuWaitDecision{ImuWaitOutcome::NoWait, std::nullopt};
    if (d.outcome == ImuWaitOutcome::Wait && stoppedClockWaitedOut(front, now))
      d.outcome = ImuWaitOutcome::ClockStopped;
    if (d.outcome == ImuWaitOutcome::Wait) {
      if (!front.counted) ++counters_.held;
      front.counted = true;
      return std::nullopt;
    }
    const double waited_s =
        d.outcome == ImuWaitOutcome::ClockStopped ? now.steady_s - front.ready_steady_s : now.ros_s - front.ready_s;
    count(front, d, waited_s);
    ReleasedEpoch<Epoch> out{std::move(front.epoch), front.time, d, waited_s};
    held_.pop_front();
    return out;
  }
  /// When the oldest held epoch's wait ends (ROS time [s]); nullopt when none is held.
  std::optional<double> deadline_s() const {
    if (held_.empty()) return std::nullopt;
    return held_.front().ready_s + max_wait_s_;
  }
  std::size_t size() const { return held_.size(); }
  bool empty() const { return held_.empty(); }
  double maxWait_s() const { return max_wait_s_; }
  const ImuWaitCounters& counters() const { return counters_; }

 private:
  struct Held {
    Epoch epoch;
    ppp::GnssTime time;
    double ready_s = 0.0;         // ROS time
    double ready_steady_s = 0.0;  // steady time
    bool counted = false;  // counted as held (it had to wait)
  };

  /// Notes when the ROS clock last moved (steady time), from the hold's calls.
  void observeClock(const HoldClock& now) {
    if (clock_ros_s_ && *clock_ros_s_ == now.ros_s) return;
    clock_ros_s_ = now.ros_s;
    clock_moved_steady_s_ = now.steady_s;
  }
  /// `h` has waited max_wait_s of steady time since it became ready and since the ROS clock last moved.
  bool stoppedClockWaitedOut(const Held& h, const HoldClock& now) const {
    return max_wait_s_ > 0.0 && now.steady_s - std::max(h.ready_steady_s, clock_moved_steady_s_) >= max_wait_s_;
  }

  void count(const Held& h, const ImuWaitDecision& d, double waited_s) {
    const bool waited_out = d.outcome == ImuWaitOutcome::WaitedOut || d.outcome == ImuWaitOutcome::ClockStopped;
    if (h.counted && d.outcome == ImuWaitOutcome::Covered) ++counters_.covered;
    if (d.outcome == ImuWaitOutcome::ImuSilent) ++counters_.silent;
    if (waited_out) {
      if (!h.counted) ++counters_.held;
      ++counters_.waited_out;
      if (d.outcome == ImuWaitOutcome::ClockStopped) ++counters_.clock_stopped;
      if (d.imu_lag_s && *d.imu_lag_s > counters_.largest_lag_s) counters_.largest_lag_s = *d.imu_lag_s;
    }
    if (d.outcome != ImuWaitOutcome::NoWait && waited_s > counters_.longest_wait_s) counters_.longest_wait_s = waited_s;
  }

  double max_wait_s_;
  std::deque<Held> held_;
  ImuWaitCounters counters_;
  std::optional<double> clock_ros_s_;  // the ROS time of the last call
  double clock_moved_steady_s_ = 0.0;  // the steady time at which the ROS clock was last seen to move
};

/// One line for the log and the diagnostics: "epoch 2026-05-13 00:00:01.000 GPS processed
/// after waiting 0.100 s for the IMU on imu/data (ros.imu.max_wait_s 0.1): its newest reading
/// 35.0 ms before the epoch, the readings after it missing (counted)"; released as
/// ClockStopped "... after waiting 0.100 s of steady time, the ROS clock standing still (a
/// bag's /clock stopped), for the IMU on ..."
std::string imuWaitedOutText(const ppp::GnssTime& epoch_time, double waited_s, const ImuWaitDecision& decision,
                             const std::string& topic, double max_wait_s);

}  // namespace ppp_ros
