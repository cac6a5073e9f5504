// rostest: ppp_smoother_node against the node integrity cases (bad stamps,
// a late re-sent epoch, a duplicated stamp, a burst overflowing the queue,
// corrections stopping): node_integrity.h.
#include "integrity/node_integrity.h"

namespace {
ppp_ros::integrity::NodeIntegrityTest* g = nullptr;
}  // namespace

TEST(SmootherNodeIntegrity, IsolatedBadStampsAreDroppedAndCountedWithoutReset) { g->checkIsolatedBadStampsDroppedAndCounted(); }

TEST(SmootherNodeIntegrity, OutputsAreMonotonicOneFixPerStampAndAsGoodAsWithoutTheBadStamps) {
  g->checkOutputsMonotonicOneFixPerStampAndAsGoodAsClean();
}

TEST(SmootherNodeIntegrity, CorrectionsDiagnosticGoesWarnThenErrorWhenTheStreamStops) {
  g->checkCorrectionsDiagnosticWarnsThenErrors();
}

TEST(SmootherNodeIntegrity, BurstOverflowingTheQueueIsCountedProcessedPlusLostEqualsSent) { g->checkBurstDropsAllCounted(); }

TEST(SmootherNodeIntegrity, BagLoopResetsOnlyWhenConfirmedAndCountsTheEpochsItDiscards) {
  g->checkLoopResetsAfterConfirmationAndCountsWhatItDiscards();
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_integrity_smoother");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ppp_ros::integrity::NodeIntegrityTest t("smoother");
  g = &t;
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
