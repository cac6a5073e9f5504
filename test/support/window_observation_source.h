#pragma once
// WindowObservationSource (tests): the epochs of another ObservationSource up
// to a time, e.g. a few hours of a day-long file, so a test runs a window.
#include <memory>

#include "ppp_bayes_tree/io/rinex/observation_source.h"

namespace ppp::test {

class WindowObservationSource : public ObservationSource {
 public:
  WindowObservationSource(std::unique_ptr<ObservationSource> inner, GnssTime until)
      : inner_(std::move(inner)), until_(until) {}
  const RinexObsHeader& header() const override { return inner_->header(); }
  ObservationRead next(ObsEpoch& epoch) override {
    const ObservationRead r = inner_->next(epoch);
    if (r == ObservationRead::Epoch && until_ < epoch.time) return ObservationRead::End;
    return r;
  }
  std::optional<ObservationProblem> error() const override { return inner_->error(); }
  double progress() const override { return inner_->progress(); }
  std::string name() const override { return inner_->name(); }

 private:
  std::unique_ptr<ObservationSource> inner_;
  GnssTime until_;
};

}  // namespace ppp::test
