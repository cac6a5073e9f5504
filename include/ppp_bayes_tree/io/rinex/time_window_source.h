#pragma once
// TimeWindowObservationSource: the epochs of another observation source inside
// a time window [start, end) (GPST; either bound may be open). Epochs before
// the start are read and dropped; the first epoch at or after the end ends the
// data (the rest of the file is not read). Used by ppp_solve --start/--end and
// by campaigns that split a day file into one-hour jobs; the epochs of an outage
// (ppp_solve --gnss-gap) are handed on empty.
#include <memory>
#include <optional>

#include "ppp_bayes_tree/io/rinex/observation_source.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// A time window [start, end), either bound open (nullopt), and optionally a GNSS
/// outage inside it: the epochs in [outage_start, outage_start + outage_s) are kept
/// with their time but without any satellite (to measure how an estimator coasts).
struct ObservationWindow {
  std::optional<GnssTime> start, end;
  std::optional<GnssTime> outage_start;
  double outage_s = 0.0;
  bool bounded() const { return start.has_value() || end.has_value() || outage_start.has_value(); }
  bool inOutage(const GnssTime& t) const { return outage_start && t - *outage_start >= 0.0 && t - *outage_start < outage_s; }
  bool contains(const GnssTime& t) const { return (!start || *start <= t) && (!end || t < *end); }
};

class TimeWindowObservationSource : public ObservationSource {
 public:
  /// Throws std::invalid_argument when `inner` is null or the window is empty (end <= start).
  TimeWindowObservationSource(std::unique_ptr<ObservationSource> inner, ObservationWindow window);

  const RinexObsHeader& header() const override { return inner_->header(); }
  ObservationRead next(ObsEpoch& epoch) override;
  std::optional<ObservationProblem> error() const override { return inner_->error(); }
  std::vector<ObservationProblem> problems() const override { return inner_->problems(); }
  double progress() const override { return ended_ ? 1.0 : inner_->progress(); }
  std::string name() const override { return inner_->name(); }

 private:
  std::unique_ptr<ObservationSource> inner_;
  ObservationWindow window_;
  bool ended_ = false;
};

}  // namespace ppp
