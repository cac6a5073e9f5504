#include "ppp_bayes_tree/evaluation/lagged_trajectory_output.h"

namespace ppp {

LaggedTrajectoryOutput::LaggedTrajectoryOutput(const std::string& csv_path, std::size_t keep_recent)
    : keep_recent_(keep_recent) {
  if (!csv_path.empty()) writer_ = std::make_unique<SmoothedTrajectoryWriter>(csv_path);
}

void LaggedTrajectoryOutput::attach(PppSmoother& smoother) {
  smoother.setMarginalizedStateSink([this](const SmoothedEpoch& e) { add(e); });
}

void LaggedTrajectoryOutput::add(const SmoothedEpoch& epoch) {
  ++handed_out_;
  if (writer_) writer_->write(epoch);
  if (keep_recent_ == 0) return;
  recent_.push_back(epoch);
  while (recent_.size() > keep_recent_) recent_.pop_front();
}

std::vector<SmoothedEpoch> LaggedTrajectoryOutput::joined(const std::vector<SmoothedEpoch>& window,
                                                          std::size_t max_states) const {
  std::vector<SmoothedEpoch> out;
  const std::size_t total = recent_.size() + window.size();
  std::size_t skip = total > max_states ? total - max_states : 0;
  out.reserve(total - skip);
  for (const auto& e : recent_) {
    if (skip > 0) {
      --skip;
      continue;
    }
    if (!window.empty() && !(e.time < window.front().time)) continue;  // never twice
    out.push_back(e);
  }
  for (const auto& e : window) {
    if (skip > 0) {
      --skip;
      continue;
    }
    out.push_back(e);
  }
  return out;
}

}  // namespace ppp
