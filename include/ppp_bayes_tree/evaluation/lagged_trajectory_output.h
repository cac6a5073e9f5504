#pragma once
// LaggedTrajectoryOutput: what a live run does with the states a fixed-lag
// PppSmoother lets go. Attached as the smoother's marginalized-state
// sink, it writes each state once to an optional SmoothedTrajectoryWriter (CSV,
// incremental) and keeps only the newest `keep_recent` of them for display (e.g.
// ppp/path/smoothed = recent() followed by the smoother's window), so memory stays
// bounded by the lag and keep_recent whatever the run's length.
#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/smoothed_trajectory_writer.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"

namespace ppp {

class LaggedTrajectoryOutput {
 public:
  /// `csv_path` empty: no file. Throws FileOpenError when the file cannot be created.
  LaggedTrajectoryOutput(const std::string& csv_path, std::size_t keep_recent);

  /// Becomes `smoother`'s marginalized-state sink (the output must outlive the
  /// attachment; attach again after replacing the smoother).
  void attach(PppSmoother& smoother);
  /// End of a run: the rest of the window through the sink (PppSmoother::finishTrajectory).
  void finish(PppSmoother& smoother) { smoother.finishTrajectory(); }

  /// The newest states handed out, oldest first (at most keep_recent).
  const std::deque<SmoothedEpoch>& recent() const { return recent_; }
  /// recent() followed by `window` (the smoother's own states), the last `max_states`.
  std::vector<SmoothedEpoch> joined(const std::vector<SmoothedEpoch>& window, std::size_t max_states) const;
  std::size_t statesHandedOut() const { return handed_out_; }
  const SmoothedTrajectoryWriter* writer() const { return writer_.get(); }

  void add(const SmoothedEpoch& epoch);

 private:
  std::unique_ptr<SmoothedTrajectoryWriter> writer_;
  std::size_t keep_recent_ = 0;
  std::deque<SmoothedEpoch> recent_;
  std::size_t handed_out_ = 0;
};

}  // namespace ppp
