// rostest: ppp_ekf_node against the node integrity cases (bad stamps,
// a late re-sent epoch, a duplicated stamp, a burst overflowing the queue,
// corrections stopping): node_integrity.h.
#include "integrity/node_integrity.h"

namespace {
ppp_ros::integrity::NodeIntegrityTest* g = nullptr;
}  // namespace

TEST(EkfNodeIntegrity, IsolatedBadStampsAreDroppedAndCountedWithoutReset) { g->checkIsolatedBadStampsDroppedAndCounted(); }

TEST(EkfNodeIntegrity, OutputsAreMonotonicOneFixPerStampAndAsGoodAsWithoutTheBadStamps) {
  g->checkOutputsMonotonicOneFixPerStampAndAsGoodAsClean();
}

TEST(EkfNodeIntegrity, CorrectionsDiagnosticGoesWarnThenErrorWhenTheStreamStops) {
  g->checkCorrectionsDiagnosticWarnsThenErrors();
}

TEST(EkfNodeIntegrity, BurstOverflowingTheQueueIsCountedProcessedPlusLostEqualsSent) { g->checkBurstDropsAllCounted(); }

TEST(EkfNodeIntegrity, BagLoopResetsOnlyWhenConfirmedAndCountsTheEpochsItDiscards) {
  g->checkLoopResetsAfterConfirmationAndCountsWhatItDiscards();
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_integrity_ekf");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ppp_ros::integrity::NodeIntegrityTest t("ekf");
  g = &t;
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
