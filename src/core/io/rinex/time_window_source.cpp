#include "ppp_bayes_tree/io/rinex/time_window_source.h"

#include <stdexcept>

namespace ppp {

TimeWindowObservationSource::TimeWindowObservationSource(std::unique_ptr<ObservationSource> inner,
                                                         ObservationWindow window)
    : inner_(std::move(inner)), window_(window) {
  if (!inner_) throw std::invalid_argument("time window: no observation source");
  if (window_.start && window_.end && *window_.end <= *window_.start)
    throw std::invalid_argument("time window: the end " + window_.end->toString(TimeSystem::GPS, 1) +
                                " is not after the start " + window_.start->toString(TimeSystem::GPS, 1));
}

ObservationRead TimeWindowObservationSource::next(ObsEpoch& epoch) {
  if (ended_) return ObservationRead::End;
  for (;;) {
    const ObservationRead read = inner_->next(epoch);
    if (read != ObservationRead::Epoch) return read;
    if (window_.end && epoch.time >= *window_.end) {
      ended_ = true;
      return ObservationRead::End;
    }
    if (window_.start && epoch.time < *window_.start) continue;
    if (window_.inOutage(epoch.time)) {
      epoch.satellites.clear();
      epoch.observations.clear();
    }
    return ObservationRead::Epoch;
  }
}

}  // namespace ppp
