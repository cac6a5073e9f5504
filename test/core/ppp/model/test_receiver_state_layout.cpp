// ReceiverStateLayout: the named receiver state members and their places in the
// state vector. GPS alone is exactly the classic (x, y, z, zwd, clock) 5-vector;
// with GPS and Galileo there are two receiver clocks, and the real measurement
// model puts each satellite's clock partial into its own system's column.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "ppp_dataset.h"
#include "test_support.h"

namespace ppp {
namespace {

TEST(ReceiverStateLayout, GpsAloneIsTheClassicFiveVector) {
  const ReceiverStateLayout layout;
  EXPECT_EQ(layout.dim(), 5);
  EXPECT_EQ(layout.position(), 0);
  EXPECT_EQ(layout.zwd(), 3);
  EXPECT_EQ(layout.clock(GnssSystem::GPS), 4);
  EXPECT_FALSE(layout.hasClock(GnssSystem::Galileo));
  EXPECT_EQ(layout, ReceiverStateLayout(std::vector<GnssSystem>{GnssSystem::GPS}));
  EXPECT_EQ(layout, ReceiverStateLayout(std::vector<GnssSystem>{}));  // nothing configured: GPS

  ReceiverState s;
  s.position_ecef_m = Eigen::Vector3d(1.0, 2.0, 3.0);
  s.zwd_m = 0.25;
  s.setClock_m(GnssSystem::GPS, 99.5);
  Eigen::VectorXd expected(5);
  expected << 1.0, 2.0, 3.0, 0.25, 99.5;
  EXPECT_EQ(s.vector(), expected);
  const ReceiverState back = ReceiverState::fromVector(expected);
  EXPECT_EQ(back.position_ecef_m, s.position_ecef_m);
  EXPECT_EQ(back.zwd_m, 0.25);
  EXPECT_EQ(back.clock_m(GnssSystem::GPS), 99.5);
  EXPECT_EQ(back.referenceClock_m(), 99.5);
}

TEST(ReceiverStateLayout, GpsAndGalileoHaveOneClockEach) {
  const ReceiverStateLayout layout({GnssSystem::GPS, GnssSystem::Galileo, GnssSystem::GPS});  // duplicate ignored
  EXPECT_EQ(layout.dim(), 6);
  EXPECT_EQ(layout.clockCount(), 2);
  EXPECT_EQ(layout.clock(GnssSystem::GPS), 4);
  EXPECT_EQ(layout.clock(GnssSystem::Galileo), 5);
  EXPECT_EQ(layout.clock(GnssSystem::BeiDou), -1);
  EXPECT_EQ(layout.clockSystems(), (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  EXPECT_TRUE(layout.isPosition(2));
  EXPECT_FALSE(layout.isPosition(3));
  EXPECT_TRUE(layout.isClock(5));
  EXPECT_EQ(layout.clockSystem(5), GnssSystem::Galileo);
  EXPECT_EQ(layout.componentName(0), "x");
  EXPECT_EQ(layout.componentName(3), "zwd");
  EXPECT_EQ(layout.componentName(5), "clock E");
  EXPECT_NE(layout, ReceiverStateLayout());

  ReceiverState s(layout);
  s.setClock_m(GnssSystem::GPS, 10.0);
  s.setClock_m(GnssSystem::Galileo, 12.5);
  const Eigen::VectorXd v = s.vector();
  ASSERT_EQ(v.size(), 6);
  EXPECT_EQ(v(4), 10.0);
  EXPECT_EQ(v(5), 12.5);
  const ReceiverState back = ReceiverState::fromVector(v, layout);
  EXPECT_EQ(back.clock_m(GnssSystem::Galileo), 12.5);
  EXPECT_EQ(back.referenceClock_m(), 10.0);  // the first configured system
}

TEST(ReceiverStateLayout, TheGradientBlockFollowsTheClocks) {
  const ReceiverStateLayout layout({GnssSystem::GPS, GnssSystem::Galileo}, true);
  EXPECT_TRUE(layout.hasGradients());
  EXPECT_FALSE(ReceiverStateLayout({GnssSystem::GPS, GnssSystem::Galileo}).hasGradients());
  EXPECT_EQ(layout.dim(), 8);  // x, y, z, zwd, clock G, clock E, G_N, G_E
  EXPECT_EQ(layout.gradientNorth(), 6);
  EXPECT_EQ(layout.gradientEast(), 7);
  EXPECT_EQ(ReceiverStateLayout().gradientNorth(), -1);
  EXPECT_TRUE(layout.isGradient(6));
  EXPECT_TRUE(layout.isGradient(7));
  EXPECT_FALSE(layout.isGradient(5));
  EXPECT_FALSE(layout.isClock(6));
  EXPECT_EQ(layout.componentName(6), "gradient N");
  EXPECT_EQ(layout.componentName(7), "gradient E");
  EXPECT_NE(layout, ReceiverStateLayout({GnssSystem::GPS, GnssSystem::Galileo}));

  ReceiverState s(layout);
  s.zwd_m = 0.2;
  s.setClock_m(GnssSystem::Galileo, 3.0);
  s.gradient_north_m = 0.0011;
  s.gradient_east_m = -0.0007;
  Eigen::VectorXd expected(8);
  expected << 0.0, 0.0, 0.0, 0.2, 0.0, 3.0, 0.0011, -0.0007;
  EXPECT_EQ(s.vector(), expected);
  const ReceiverState back = ReceiverState::fromVector(expected, layout);
  EXPECT_EQ(back.gradient_north_m, 0.0011);
  EXPECT_EQ(back.gradient_east_m, -0.0007);
  // Without the block the gradients are not part of the vector.
  s.layout = ReceiverStateLayout({GnssSystem::GPS, GnssSystem::Galileo});
  EXPECT_EQ(s.vector().size(), 6);
}

TEST(ReceiverStateLayout, TheRealModelPutsTheClockPartialIntoTheSatellitesSystemColumn) {
  PPP_REQUIRE_SHARED_DATA();
  test::LoadedDataset ds(test::zim2Dataset());
  SignalSelector selector(ds.reader->header(), {}, ds.biases.get());
  ObsEpoch epoch;
  ds.reader->next(epoch);
  ds.reader->next(epoch);  // second epoch: products cover the emission times
  const std::vector<DualFrequencyObservation> obs = selector.select(epoch).observations;
  std::vector<ArcId> arcs;
  for (std::size_t i = 0; i < obs.size(); ++i) arcs.push_back(static_cast<ArcId>(i + 1));

  // Galileo first: the GPS clock is the second clock column (index 5).
  const ReceiverStateLayout layout({GnssSystem::Galileo, GnssSystem::GPS});
  ReceiverState x(layout);
  x.position_ecef_m = ds.paths.truth_ecef_m;
  x.zwd_m = 0.1;
  x.setClock_m(GnssSystem::GPS, 50.0);
  x.setClock_m(GnssSystem::Galileo, -700.0);  // must not enter GPS predictions
  const EpochMeasurements em = ds.model->evaluate(obs, arcs, x, nullptr);
  ASSERT_GE(em.used.size(), 6u);
  ReceiverState gps_only;
  gps_only.position_ecef_m = x.position_ecef_m;
  gps_only.zwd_m = x.zwd_m;
  gps_only.setClock_m(GnssSystem::GPS, 50.0);
  const EpochMeasurements reference = ds.model->evaluate(obs, arcs, gps_only, nullptr);
  ASSERT_EQ(reference.used.size(), em.used.size());
  for (std::size_t i = 0; i < em.used.size(); ++i) {
    const SatelliteMeasurement& m = em.used[i];
    ASSERT_EQ(m.satellite.system, GnssSystem::GPS);
    ASSERT_EQ(m.jacobian.size(), 6);
    EXPECT_EQ(m.jacobian(layout.clock(GnssSystem::GPS)), 1.0);
    EXPECT_EQ(m.jacobian(layout.clock(GnssSystem::Galileo)), 0.0);
    // The same prediction and partials as with the GPS-only 5-vector.
    EXPECT_EQ(m.predicted_code_m, reference.used[i].predicted_code_m);
    EXPECT_EQ(m.jacobian.head<4>(), reference.used[i].jacobian.head<4>());
    EXPECT_EQ(reference.used[i].jacobian(4), 1.0);
  }

  // A system without a clock in the layout: its satellites are rejected with the reason.
  const ReceiverStateLayout galileo_only({GnssSystem::Galileo});
  ReceiverState g(galileo_only);
  g.position_ecef_m = x.position_ecef_m;
  const EpochMeasurements none = ds.model->evaluate(obs, arcs, g, nullptr);
  EXPECT_TRUE(none.used.empty());
  ASSERT_FALSE(none.rejected.empty());
  for (const auto& r : none.rejected) EXPECT_EQ(r.reason, RejectionReason::NoReceiverClock) << r.text();
}

}  // namespace
}  // namespace ppp
