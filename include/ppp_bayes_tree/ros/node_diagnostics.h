#pragma once
// The ROS node's diagnostics (ppp_node.h, /diagnostics): the tasks "inputs",
// "corrections" (or "live streams" on the live input), "solution" and "ambiguity
// resolution", each filling a DiagnosticStatusWrapper from the counters and state of
// the node's inputs (node_inputs.h) and outputs (node_outputs.h). Levels: ERROR when
// the corrections stopped (observations ahead by more than the ERROR threshold) or an
// observation stream stalled past its ERROR threshold; WARN for losses, stale or late
// corrections, no input yet, no solution, a float solution without phase information.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/time.h>

#include "ppp_bayes_tree/ros/gnss_stream_subscriber.h"
#include "ppp_bayes_tree/ros/node_inputs.h"
#include "ppp_bayes_tree/ros/node_outputs.h"
#include "ppp_bayes_tree/ros/node_options.h"

namespace ppp_ros {

/// A note of the node at start: its text and whether it is a warning.
struct StartNote {
  bool warning = false;
  std::string text;
};
/// The smoother node's cost, said at start: the full smoother (smoother.fixed_lag_s 0)
/// warns what it costs; a fixed lag says that memory and update time are bounded and
/// where the states leaving the lag go (ros.smoothed.trajectory_csv).
StartNote smootherCostNote(double fixed_lag_s, const std::string& trajectory_csv);

/// What the node says once set up: its configuration's source, the ANTEX files, the
/// bias file, the inputs it waits for (the two topics, or the live stream topics) and
/// the attitude source. `resolve`: the node handle's name resolution.
StartNote startSummary(const RosNodeOptions& options, const std::string& config_source, std::size_t antex_files,
                       const std::vector<std::string>& live_topics,
                       const std::function<std::string(const std::string&)>& resolve);

class NodeDiagnostics {
 public:
  /// `start`: the wall time the first input rate is counted from.
  NodeDiagnostics(const RosNodeOptions& options, ros::WallTime start);

  /// "inputs": messages and rates since the last report (wall clock `now`), stamps dropped
  /// (and epochs the outputs did not publish), resets, messages lost before the node, the
  /// attitude source (the outputs' attitude counters).
  void inputs(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in, const NodeOutputs& out,
              ros::WallTime now);
  /// "corrections" (topic input): the buffer, the batches' age, how far the observations are
  /// ahead, the satellite-epochs the outputs found without corrections.
  void corrections(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in, const NodeOutputs& out) const;
  /// "solution": the last status; the smoother's figures when `smoother` is not nullptr.
  void solution(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in, const NodeOutputs& out,
                const ppp::SmoothedTrajectoryProvider* smoother, std::size_t estimator_restarts) const;
  /// "live streams" (live input): product mode, cost figures, each subscriber and stream
  /// (`now_s`: ROS time, the clock of the chunks' arrival).
  void live(diagnostic_updater::DiagnosticStatusWrapper& s, const NodeInputs& in, const NodeOutputs& out,
            const std::vector<std::unique_ptr<GnssStreamSubscriber>>& subscribers, double estimator_cpu_s,
            double now_s) const;
  /// "ambiguity resolution": the phase information and the fix figures.
  void ambiguities(diagnostic_updater::DiagnosticStatusWrapper& s, bool enabled, const PhaseBiasChoice& phase,
                   const NodeOutputs& out) const;

 private:
  RosNodeOptions options_;
  std::size_t obs_at_last_diag_ = 0, corr_at_last_diag_ = 0;
  std::size_t lost_at_last_diag_ = 0;  // messages lost (both topics) at the last inputs diagnostic
  ros::WallTime last_diag_time_;
};

}  // namespace ppp_ros
