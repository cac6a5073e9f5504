// EpochTimeGuard: an isolated bad stamp (GPS week 0, week 65535, +1 h, +1 day, an
// epoch re-sent 100 s late) is dropped with its reason and never resets; a
// sustained jump back (a rosbag loop) resets only once `confirm_epochs`
// consistent epochs confirm it, and releases them; every epoch pushed comes out
// exactly once (accepted or dropped). The bad stamps are the cases.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/io/epoch_time_guard.h"

namespace {

using ppp::EpochTimeGuard;
using ppp::GnssTime;
using ppp::TimeDropReason;
using Guard = EpochTimeGuard<int>;

const GnssTime kStart = GnssTime::fromGpsWeek(2418, 259200.0);  // 2026-05-13 00:00 GPST (ZIM2 day)

struct Tally {
  std::vector<int> accepted;
  std::vector<std::pair<int, TimeDropReason>> dropped;
  int resets = 0;
  void add(const Guard::Outcome& o) {
    for (const auto& e : o.accepted) accepted.push_back(e.payload);
    for (const auto& d : o.dropped) dropped.emplace_back(d.payload, d.reason);
    if (o.reset_step_s) ++resets;
  }
};

/// 1-Hz epochs 0..9 with epoch 5 replaced by `bad`; payload = index.
Tally runWithBadFifth(const GnssTime& bad, ppp::EpochTimeGuardOptions options = {}) {
  Guard g(options);
  Tally t;
  for (int k = 0; k < 10; ++k) t.add(g.push(k == 5 ? bad : kStart + k, k));
  return t;
}

void expectIsolatedDrop(const Tally& t, const char* what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(t.resets, 0);
  ASSERT_EQ(t.dropped.size(), 1u);
  EXPECT_EQ(t.dropped[0].first, 5);
  EXPECT_EQ(t.dropped[0].second, TimeDropReason::UnconfirmedJump);
  EXPECT_EQ(t.accepted, (std::vector<int>{0, 1, 2, 3, 4, 6, 7, 8, 9}));
}

TEST(EpochTimeGuard, NormalStreamIsAcceptedAsItComes) {
  const Tally t = runWithBadFifth(kStart + 5.0);
  EXPECT_EQ(t.accepted, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_TRUE(t.dropped.empty());
}

TEST(EpochTimeGuard, IsolatedBadStampsAreDroppedWithoutReset) {
  expectIsolatedDrop(runWithBadFifth(GnssTime::fromGpsWeek(0, 259205.0)), "week 0");
  expectIsolatedDrop(runWithBadFifth(GnssTime::fromGpsWeek(65535, 259205.0)), "week 65535");
  expectIsolatedDrop(runWithBadFifth(kStart + 5.0 + 3600.0), "+1 h");
  expectIsolatedDrop(runWithBadFifth(kStart + 5.0 - 3600.0), "-1 h");
  expectIsolatedDrop(runWithBadFifth(kStart + 5.0 + 86400.0), "+1 day");
  expectIsolatedDrop(runWithBadFifth(kStart + 4.0 - 100.0), "re-sent 100 s late");
}

TEST(EpochTimeGuard, DuplicateAndShortStepBackAreDroppedAtOnce) {
  Guard g;
  Tally t;
  for (int k = 0; k < 5; ++k) t.add(g.push(kStart + k, k));
  t.add(g.push(kStart + 4.0, 50));   // the same stamp again
  t.add(g.push(kStart + 1.0, 51));   // 3 s back: out of order
  t.add(g.push(kStart + 5.0, 5));
  ASSERT_EQ(t.dropped.size(), 2u);
  EXPECT_EQ(t.dropped[0], std::make_pair(50, TimeDropReason::Duplicate));
  EXPECT_EQ(t.dropped[1], std::make_pair(51, TimeDropReason::OutOfOrder));
  EXPECT_EQ(t.accepted.back(), 5);
  EXPECT_EQ(t.resets, 0);
}

TEST(EpochTimeGuard, BagLoopResetsAfterConfirmationAndLosesNothing) {
  Guard g;  // confirm_epochs 3
  Tally t;
  for (int k = 0; k < 300; ++k) t.add(g.push(kStart + k, k));
  // The bag starts again: 300 s back.
  Guard::Outcome o1 = g.push(kStart + 0.0, 1000);
  Guard::Outcome o2 = g.push(kStart + 1.0, 1001);
  EXPECT_TRUE(o1.accepted.empty() && o2.accepted.empty());
  EXPECT_EQ(g.held(), 2u);
  Guard::Outcome o3 = g.push(kStart + 2.0, 1002);
  ASSERT_TRUE(o3.reset_step_s.has_value());
  EXPECT_DOUBLE_EQ(*o3.reset_step_s, -299.0);
  ASSERT_EQ(o3.accepted.size(), 3u);
  EXPECT_EQ(o3.accepted[0].payload, 1000);
  EXPECT_EQ(o3.accepted[2].payload, 1002);
  EXPECT_EQ(*g.lastAccepted(), kStart + 2.0);
  // The new time line goes on normally.
  Guard::Outcome o4 = g.push(kStart + 3.0, 1003);
  ASSERT_EQ(o4.accepted.size(), 1u);
  EXPECT_FALSE(o4.reset_step_s);
}

TEST(EpochTimeGuard, SustainedForwardJumpIsAcceptedWithoutReset) {
  Guard g;
  for (int k = 0; k < 5; ++k) g.push(kStart + k, k);
  // An outage of 2 h, then data again: held for 3 epochs, released, no reset.
  g.push(kStart + 7200.0, 10);
  g.push(kStart + 7201.0, 11);
  const Guard::Outcome o = g.push(kStart + 7202.0, 12);
  EXPECT_FALSE(o.reset_step_s);
  ASSERT_TRUE(o.forward_jump_s);
  EXPECT_DOUBLE_EQ(*o.forward_jump_s, 7196.0);
  EXPECT_EQ(o.accepted.size(), 3u);
}

TEST(EpochTimeGuard, TwoDifferentBadStampsInARowAreBothDropped) {
  Guard g;
  Tally t;
  for (int k = 0; k < 5; ++k) t.add(g.push(kStart + k, k));
  t.add(g.push(GnssTime::fromGpsWeek(0, 10.0), 100));      // week 0
  t.add(g.push(GnssTime::fromGpsWeek(65535, 10.0), 101));  // then week 65535: not consistent with the first
  t.add(g.push(kStart + 5.0, 5));
  EXPECT_EQ(t.resets, 0);
  ASSERT_EQ(t.dropped.size(), 2u);
  EXPECT_EQ(t.dropped[0].first, 100);
  EXPECT_EQ(t.dropped[1].first, 101);
  EXPECT_EQ(t.accepted.back(), 5);
}

TEST(EpochTimeGuard, PassingOutOfOrderOnKeepsTheNewestTime) {
  ppp::EpochTimeGuardOptions o;
  o.drop_out_of_order = false;
  Guard g(o);
  g.push(kStart + 30.0, 1);
  const Guard::Outcome a = g.push(kStart + 0.0, 2);  // 30 s back, passed on
  ASSERT_EQ(a.accepted.size(), 1u);
  EXPECT_EQ(*g.lastAccepted(), kStart + 30.0);
  const Guard::Outcome b = g.push(kStart + 30.0 - 3600.0, 3);  // beyond the window: held
  EXPECT_TRUE(b.accepted.empty());
  EXPECT_EQ(g.held(), 1u);
}

TEST(EpochTimeGuard, ConfirmOneResetsAtOnceAndClearReturnsTheHeld) {
  ppp::EpochTimeGuardOptions o;
  o.confirm_epochs = 1;
  Guard g(o);
  g.push(kStart + 300.0, 1);
  const Guard::Outcome a = g.push(kStart, 2);
  ASSERT_TRUE(a.reset_step_s);
  EXPECT_EQ(a.accepted.size(), 1u);
  Guard g3;
  g3.push(kStart + 300.0, 1);
  g3.push(kStart, 2);
  const auto held = g3.clear();
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].payload, 2);
  EXPECT_FALSE(g3.lastAccepted());
}

TEST(EpochTimeGuard, ConfirmHeldReleasesACandidateJumpAtOnce) {
  Guard g;
  g.push(kStart + 600.0, 1);
  g.push(kStart + 630.0, 2);
  g.push(kStart + 0.0, 3);  // 630 s back: held
  EXPECT_EQ(g.held(), 1u);
  EXPECT_EQ(*g.firstHeld(), kStart);
  const Guard::Outcome o = g.confirmHeld();
  ASSERT_TRUE(o.reset_step_s);
  EXPECT_DOUBLE_EQ(*o.reset_step_s, -630.0);
  ASSERT_EQ(o.accepted.size(), 1u);
  EXPECT_EQ(o.accepted[0].payload, 3);
  EXPECT_EQ(*g.lastAccepted(), kStart);
  const Guard::Outcome none = g.confirmHeld();
  EXPECT_TRUE(none.accepted.empty());
  EXPECT_FALSE(none.reset_step_s);
}

TEST(EpochTimeGuard, ReasonsHaveText) {
  EXPECT_EQ(ppp::text(TimeDropReason::Duplicate), "duplicate stamp");
  EXPECT_NE(ppp::text(TimeDropReason::UnconfirmedJump).find("isolated"), std::string::npos);
}

}  // namespace
