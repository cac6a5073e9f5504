// TimeWindowObservationSource: the window's bounds and a GNSS outage (epochs kept
// with their time, without satellites: ppp_solve --gnss-gap).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/io/rinex/time_window_source.h"

namespace ppp {
namespace {

/// Ten epochs 1 s apart from GPS week 2381, 0 s, each with one satellite and one observation.
std::vector<ObsEpoch> tenEpochs() {
  std::vector<ObsEpoch> epochs(10);
  for (int k = 0; k < 10; ++k) {
    epochs[k].time = GnssTime::fromGpsWeek(2381, k);
    epochs[k].satellites.push_back(SatelliteObservations{SatelliteId{}, 0, 1});
    epochs[k].observations.resize(1);
  }
  return epochs;
}

TEST(TimeWindowObservationSource, KeepsTheEpochsOfAnOutageWithoutSatellites) {
  const RinexObsHeader header;
  const std::vector<ObsEpoch> epochs = tenEpochs();
  ObservationWindow window;
  window.start = GnssTime::fromGpsWeek(2381, 1.0);
  window.end = GnssTime::fromGpsWeek(2381, 9.0);
  window.outage_start = GnssTime::fromGpsWeek(2381, 3.0);
  window.outage_s = 2.5;  // epochs 3, 4, 5
  TimeWindowObservationSource source(std::make_unique<InMemoryObservationSource>(header, epochs), window);
  ObsEpoch e;
  std::vector<int> seconds, satellites;
  while (source.next(e) == ObservationRead::Epoch) {
    seconds.push_back(static_cast<int>(e.time - GnssTime::fromGpsWeek(2381, 0.0)));
    satellites.push_back(static_cast<int>(e.satellites.size() + e.observations.size()));
  }
  EXPECT_EQ(seconds, (std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(satellites, (std::vector<int>{2, 2, 0, 0, 0, 2, 2, 2}));
  EXPECT_TRUE(window.bounded());
  ObservationWindow outage_only;
  outage_only.outage_start = window.outage_start;
  EXPECT_TRUE(outage_only.bounded());
  EXPECT_FALSE(ObservationWindow{}.bounded());
}

}  // namespace
}  // namespace ppp
