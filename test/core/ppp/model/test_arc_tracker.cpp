// ArcTracker: cycle-slip detection (Melbourne-Wuebbena, geometry-free), LLI,
// data gaps, refused epochs; on synthetic arcs and on real ZIM2 / CCJ2 data.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/types/constants.h"
#include "test_support.h"

namespace ppp {
namespace {

// GPS L1/L2 frequencies (IS-GPS-200, 154 and 120 times 10.23 MHz).
constexpr double kF1 = 1575.42e6, kF2 = 1227.60e6;
constexpr double kLambda1 = kSpeedOfLight_mps / kF1, kLambda2 = kSpeedOfLight_mps / kF2;
const GnssTime kT0 = GnssTime::fromGpsWeek(2418, 259200.0);

/// Synthetic dual-frequency observations of a few satellites: smooth geometry and
/// ionosphere, Gaussian code (0.3 m) and phase (2 mm) noise, ambiguities that
/// change by injected slips.
class Simulator {
 public:
  explicit Simulator(unsigned seed) : rng_(seed) {}
  std::map<int, std::pair<int, int>> slip_at;  // epoch index -> (dN1, dN2) applied to G05
  DualFrequencyObservation observe(int prn, double t_s, int epoch) {
    if (prn == 5 && slip_at.count(epoch)) {
      n1_[prn] += slip_at[epoch].first;
      n2_[prn] += slip_at[epoch].second;
    }
    const double rho = 2.2e7 + 3000.0 * prn + 450.0 * t_s + 2e-3 * t_s * t_s * 0.5;
    const double iono1 = 3.0 + 0.3 * prn + 1.5 * std::sin(2 * kPi * t_s / 10800.0 + prn);
    const double gamma = (kF1 / kF2) * (kF1 / kF2);
    DualFrequencyObservation o;
    o.satellite = SatelliteId{GnssSystem::GPS, prn};
    o.time = kT0 + t_s;
    o.frequency1_hz = kF1;
    o.frequency2_hz = kF2;
    o.code1_m = rho + iono1 + code_(rng_);
    o.code2_m = rho + gamma * iono1 + code_(rng_);
    o.phase1_cycles = (rho - iono1 + phase_(rng_)) / kLambda1 + 1000.0 * prn + n1_[prn];
    o.phase2_cycles = (rho - gamma * iono1 + phase_(rng_)) / kLambda2 - 777.0 * prn + n2_[prn];
    return o;
  }

 private:
  std::mt19937 rng_;
  std::normal_distribution<double> code_{0.0, 0.3}, phase_{0.0, 0.002};
  std::map<int, double> n1_, n2_;
};

struct RunSummary {
  std::vector<std::pair<int, std::string>> new_arcs;  // (epoch, reason) for G05 after epoch 0
  std::size_t false_other = 0;                        // new arcs of other satellites after epoch 0
};

RunSummary run(Simulator& sim, double interval_s, int epochs, const CycleSlipOptions& options = {}) {
  ArcTracker tracker(options);
  RunSummary summary;
  std::vector<DualFrequencyObservation> obs;
  for (int k = 0; k < epochs; ++k) {
    obs.clear();
    for (int prn : {5, 7, 13, 30}) obs.push_back(sim.observe(prn, k * interval_s, k));
    const auto r = tracker.process(kT0 + k * interval_s, obs);
    EXPECT_TRUE(r.accepted);
    for (const auto& s : r.satellites) {
      if (!s.new_arc || k == 0) continue;
      if (s.satellite.prn == 5) summary.new_arcs.emplace_back(k, s.reason);
      else ++summary.false_other;
    }
  }
  return summary;
}

TEST(ArcTracker, ThresholdScalingLaw) {
  const CycleSlipOptions o;
  // threshold = 0.030 m + 0.0006 m/s * dt (documented defaults in arc_tracker.h).
  EXPECT_NEAR(o.geometryFreeThreshold_m(1.0), 0.0306, 1e-12);
  EXPECT_NEAR(o.geometryFreeThreshold_m(30.0), 0.048, 1e-12);
  EXPECT_NEAR(o.geometryFreeThreshold_m(1e5), o.gf_threshold_max_m, 1e-12);
  // (1,1) slip moves GF by lambda1 - lambda2 = -5.4 cm: above the 30 s threshold.
  EXPECT_GT(std::abs(kLambda1 - kLambda2), o.geometryFreeThreshold_m(30.0));
}

TEST(ArcTracker, CleanSyntheticArcsHaveNoFalseSlips) {
  for (double interval : {1.0, 30.0}) {
    Simulator sim(42);
    const int epochs = interval == 1.0 ? 4 * 3600 : 2 * 2880;  // 4 h at 1 s, 2 days at 30 s
    const auto s = run(sim, interval, epochs);
    EXPECT_TRUE(s.new_arcs.empty()) << "interval " << interval << ": " << s.new_arcs.front().second;
    EXPECT_EQ(s.false_other, 0u) << "interval " << interval;
  }
}

TEST(ArcTracker, InjectedSlipsAreDetectedAtTheirEpoch) {
  for (double interval : {1.0, 30.0}) {
    Simulator sim(7);
    // (1,0), (0,1), (1,1), (9,7) cycles; (9,7) leaves GF almost unchanged
    // (9 lambda1 - 7 lambda2 = 3.5 mm) and is caught by MW (2 wide-lane cycles).
    sim.slip_at = {{40, {1, 0}}, {80, {0, 1}}, {120, {1, 1}}, {160, {9, 7}}, {200, {-3, 0}}};
    const auto s = run(sim, interval, 240);
    ASSERT_EQ(s.new_arcs.size(), 5u) << "interval " << interval;
    int i = 0;
    for (const auto& [epoch, dn] : sim.slip_at) {
      EXPECT_EQ(s.new_arcs[i].first, epoch) << "interval " << interval << " slip " << dn.first << "," << dn.second;
      ++i;
    }
    EXPECT_NE(s.new_arcs[3].second.find("Melbourne-Wubbena jump"), std::string::npos) << s.new_arcs[3].second;
    EXPECT_NE(s.new_arcs[2].second.find("geometry-free jump"), std::string::npos) << s.new_arcs[2].second;
    EXPECT_EQ(s.false_other, 0u);
  }
}

TEST(ArcTracker, LossOfLockGapsAndEndedArcs) {
  Simulator sim(3);
  ArcTracker tracker;
  std::set<ArcId> ids;
  auto epoch = [&](int k, std::vector<int> prns, bool lli_g07 = false) {
    std::vector<DualFrequencyObservation> obs;
    for (int prn : prns) {
      obs.push_back(sim.observe(prn, k * 30.0, k));
      if (prn == 7 && lli_g07) obs.back().loss_of_lock1 = true;
    }
    return tracker.process(kT0 + k * 30.0, obs);
  };
  auto r = epoch(0, {5, 7});
  EXPECT_EQ(r.newArcCount(), 2u);
  EXPECT_EQ(r.satellites[0].reason, "new satellite");
  const ArcId g05_first = r.satellites[0].arc, g07_first = r.satellites[1].arc;
  EXPECT_NE(g05_first, g07_first);
  for (int k = 1; k < 5; ++k) EXPECT_EQ(epoch(k, {5, 7}).newArcCount(), 0u);
  r = epoch(5, {5, 7}, true);
  EXPECT_FALSE(r.satellites[0].new_arc);
  EXPECT_TRUE(r.satellites[1].new_arc);
  EXPECT_EQ(r.satellites[1].start_reason, ArcStartReason::LossOfLock);
  EXPECT_EQ(r.satellites[1].reason, "LLI set on L1");
  ASSERT_EQ(r.ended.size(), 1u);
  EXPECT_EQ(r.ended[0].arc, g07_first);
  EXPECT_EQ(r.ended[0].epochs, 5u);
  // G05 missing from epochs 6..9 (last seen at epoch 5 = 150 s): the interval is
  // 30 s, the max gap 3 intervals = 90 s; at epoch 9 (120 s absent) its arc ends.
  EXPECT_DOUBLE_EQ(tracker.maxGap_s(), 90.0);
  for (int k = 6; k < 9; ++k) EXPECT_TRUE(epoch(k, {7}).ended.empty());
  r = epoch(9, {7});
  ASSERT_EQ(r.ended.size(), 1u);
  EXPECT_EQ(r.ended[0].arc, g05_first);
  EXPECT_EQ(r.ended[0].reason, "not observed for 120 s > 90 s");
  EXPECT_FALSE(tracker.currentArc(SatelliteId{GnssSystem::GPS, 5}));
  r = epoch(10, {5, 7});
  EXPECT_TRUE(r.satellites[0].new_arc);
  EXPECT_EQ(r.satellites[0].start_reason, ArcStartReason::DataGap);
  EXPECT_EQ(r.satellites[0].reason, "data gap 150 s > 90 s");
  // Ids are unique over the run.
  for (ArcId id : {g05_first, g07_first, r.satellites[0].arc, r.satellites[1].arc}) ids.insert(id);
  EXPECT_EQ(ids.size(), 4u);
  const auto ended = tracker.finish();
  EXPECT_EQ(ended.size(), 2u);
  EXPECT_EQ(ended[0].reason, "end of data");
}

// A gap longer than the maximum (3 intervals of 1 s) but within bridge_max_gap_s
// (6 s) keeps the arc, marked bridged with its geometry-free jump; without the
// bound, and beyond it, the gap ends the arc; a slip across a bridged gap still
// starts a new arc (Melbourne-Wubbena) when the slip repair is off.
TEST(ArcTracker, BridgedGapKeepsTheArcOnlyWithinItsBound) {
  const auto run_gap = [](std::optional<double> bridge_s, int gap_epochs, std::pair<int, int> slip) {
    Simulator sim(5);
    CycleSlipOptions o;
    o.bridge_max_gap_s = bridge_s;
    o.slip_repair.enabled = false;
    ArcTracker tracker(o);
    const int back = 10 + gap_epochs;
    sim.slip_at[back] = slip;
    ArcEpochResult r;
    for (int k = 0; k <= 10; ++k) r = tracker.process(kT0 + k * 1.0, {sim.observe(5, k * 1.0, k)});
    r = tracker.process(kT0 + back * 1.0, {sim.observe(5, back * 1.0, back)});
    return r.satellites.at(0);
  };
  const SatelliteArcStatus bridged = run_gap(6.0, 6, {0, 0});
  EXPECT_FALSE(bridged.new_arc);
  EXPECT_DOUBLE_EQ(bridged.bridged_gap_s, 6.0);
  ASSERT_TRUE(bridged.bridged_gf_jump_m);
  EXPECT_LT(std::abs(*bridged.bridged_gf_jump_m), 0.02);
  const SatelliteArcStatus unbridged = run_gap(std::nullopt, 6, {0, 0});
  EXPECT_TRUE(unbridged.new_arc);
  EXPECT_EQ(unbridged.start_reason, ArcStartReason::DataGap);
  const SatelliteArcStatus too_long = run_gap(6.0, 7, {0, 0});
  EXPECT_TRUE(too_long.new_arc);
  EXPECT_EQ(too_long.start_reason, ArcStartReason::DataGap);
  const SatelliteArcStatus slipped = run_gap(6.0, 6, {3, 0});
  EXPECT_TRUE(slipped.new_arc);
  EXPECT_EQ(slipped.start_reason, ArcStartReason::MelbourneWuebbenaJump);
  EXPECT_DOUBLE_EQ(slipped.bridged_gap_s, 0.0);
}

// A slip across a bridged 30-s gap (60 epochs before it at 1 Hz) is repaired
// (slip_repair.h): the arc goes on with its phases corrected by (dN1, dN2) from
// then on, and the next epoch passes the slip tests; with the repair off, or
// without a bridging estimator, a new arc starts.
TEST(ArcTracker, SlipAcrossABridgedGapIsRepaired) {
  struct Run {
    SatelliteArcStatus back, next;
  };
  const auto run = [](std::optional<double> bridge_s, bool repair, std::pair<int, int> slip) {
    Simulator sim(8);
    CycleSlipOptions o;
    o.bridge_max_gap_s = bridge_s;
    o.slip_repair.enabled = repair;
    ArcTracker tracker(o);
    constexpr int kBack = 59 + 30;
    sim.slip_at[kBack] = slip;
    for (int k = 0; k < 60; ++k) tracker.process(kT0 + k * 1.0, {sim.observe(5, k * 1.0, k)});
    Run r;
    r.back = tracker.process(kT0 + kBack * 1.0, {sim.observe(5, kBack * 1.0, kBack)}).satellites.at(0);
    r.next = tracker.process(kT0 + (kBack + 1) * 1.0, {sim.observe(5, kBack + 1.0, kBack + 1)}).satellites.at(0);
    return r;
  };
  for (const auto& slip : {std::pair{3, -2}, std::pair{-40, -31}, std::pair{1, 1}}) {
    const Run r = run(60.0, true, slip);
    EXPECT_FALSE(r.back.new_arc) << r.back.reason;
    ASSERT_TRUE(r.back.slip_repair);
    EXPECT_EQ(r.back.slip_repair->outcome, SlipRepairOutcome::Repaired) << r.back.slip_repair->text;
    EXPECT_EQ(r.back.phase_correction1_cycles, slip.first) << r.back.slip_repair->text;
    EXPECT_EQ(r.back.phase_correction2_cycles, slip.second) << r.back.slip_repair->text;
    EXPECT_DOUBLE_EQ(r.back.bridged_gap_s, 30.0);
    ASSERT_TRUE(r.back.bridged_gf_jump_m);
    EXPECT_LT(std::abs(*r.back.bridged_gf_jump_m), 0.02);
    EXPECT_FALSE(r.next.new_arc) << r.next.reason;
    EXPECT_EQ(r.next.arc, r.back.arc);
    EXPECT_FALSE(r.next.slip_repair);
    EXPECT_EQ(r.next.phase_correction1_cycles, slip.first);
    EXPECT_EQ(r.next.phase_correction2_cycles, slip.second);
  }
  const Run off = run(60.0, false, {3, -2});
  EXPECT_TRUE(off.back.new_arc);
  EXPECT_FALSE(off.back.slip_repair);
  EXPECT_EQ(off.back.phase_correction1_cycles, 0);
  const Run unbridged = run(std::nullopt, true, {3, -2});
  EXPECT_TRUE(unbridged.back.new_arc);
  EXPECT_EQ(unbridged.back.start_reason, ArcStartReason::DataGap);
  EXPECT_FALSE(unbridged.back.slip_repair);
}

// A repair with candidates (the unique rule off, a 2.5-cycle search: the GPS wide
// lanes 2 either side of the true one give an integer L1 too) applies the nearest the
// MW jump; the estimator's choice of another makes that epoch's phases corrected by it
// (chooseRepairCandidate), a slip that is not a candidate is refused; an arc the
// estimator's gap bridge ends starts again with a new id and its observed phases
// (restartArc), and goes on from there.
TEST(ArcTracker, RepairCandidatesAreChosenAndEndedArcsRestart) {
  Simulator sim(8);
  CycleSlipOptions o;
  o.bridge_max_gap_s = 60.0;
  o.slip_repair.max_wide_lane_sigma_cycles = 1e-3;   // never unique: candidates
  o.slip_repair.min_candidate_half_width_cycles = 2.5;
  ArcTracker tracker(o);
  constexpr int kBack = 59 + 30;
  sim.slip_at[kBack] = {3, -2};
  for (int k = 0; k < 60; ++k) tracker.process(kT0 + k * 1.0, {sim.observe(5, k * 1.0, k)});
  const DualFrequencyObservation obs = sim.observe(5, kBack * 1.0, kBack);
  const SatelliteArcStatus back = tracker.process(kT0 + kBack * 1.0, {obs}).satellites.at(0);
  ASSERT_TRUE(back.slip_repair);
  ASSERT_TRUE(back.slip_repair->accepted()) << back.slip_repair->text;
  ASSERT_EQ(back.slip_repair->alternatives.size(), 2u) << back.slip_repair->text;
  EXPECT_EQ(back.phase_correction1_cycles, 3) << back.slip_repair->text;
  EXPECT_EQ(back.phase_correction2_cycles, -2) << back.slip_repair->text;
  const SatelliteId g05 = obs.satellite;
  EXPECT_FALSE(tracker.chooseRepairCandidate(g05, {99, 99, 99.0}));
  const SlipCandidate other = back.slip_repair->alternatives[0];
  const auto chosen = tracker.chooseRepairCandidate(g05, other);
  ASSERT_TRUE(chosen);
  EXPECT_EQ(chosen->arc, back.arc);
  EXPECT_EQ(chosen->phase_correction1_cycles, other.dn1_cycles);
  EXPECT_EQ(chosen->phase_correction2_cycles, other.dn2_cycles);
  EXPECT_DOUBLE_EQ(chosen->phase1_cycles, obs.phase1_cycles - static_cast<double>(other.dn1_cycles));
  EXPECT_DOUBLE_EQ(chosen->phase2_cycles, obs.phase2_cycles - static_cast<double>(other.dn2_cycles));
  ASSERT_TRUE(chosen->slip_repair);
  EXPECT_EQ(chosen->slip_repair->dn1_cycles, other.dn1_cycles);
  EXPECT_NE(chosen->slip_repair->text.find("chosen by the gap bridge"), std::string::npos);
  // The gap bridge ended the arc: a new one from this epoch, the phases as observed.
  EXPECT_FALSE(tracker.restartArc(SatelliteId{GnssSystem::GPS, 7}, "not observed"));
  const auto restarted = tracker.restartArc(g05, "slip 4.1 cycles");
  ASSERT_TRUE(restarted);
  EXPECT_TRUE(restarted->new_arc);
  EXPECT_GT(restarted->arc, back.arc);
  EXPECT_DOUBLE_EQ(restarted->phase1_cycles, obs.phase1_cycles);
  EXPECT_EQ(restarted->phase_correction1_cycles, 0);
  EXPECT_EQ(tracker.currentArc(g05), restarted->arc);
  EXPECT_FALSE(tracker.chooseRepairCandidate(g05, back.slip_repair->applied()));
  const SatelliteArcStatus next =
      tracker.process(kT0 + (kBack + 1) * 1.0, {sim.observe(5, kBack + 1.0, kBack + 1)}).satellites.at(0);
  EXPECT_FALSE(next.new_arc) << next.reason;
  EXPECT_EQ(next.arc, restarted->arc);
  EXPECT_EQ(next.phase_correction1_cycles, 0);
}

// The tracker subtracts an arc's repaired slips from its phases (the one place they
// are applied): SatelliteArcStatus::phase1_cycles and phase2_cycles are the observed
// phases minus the corrections, the observed ones again once a slip starts a new arc.
TEST(ArcTracker, TheArcsPhasesAreTheObservedOnesMinusItsRepairedSlips) {
  Simulator sim(8);
  CycleSlipOptions o;
  o.bridge_max_gap_s = 60.0;
  ArcTracker tracker(o);
  constexpr int kBack = 59 + 30;
  sim.slip_at[kBack] = {3, -2};
  sim.slip_at[kBack + 2] = {5, 0};  // not across a gap: a new arc
  for (int k = 0; k < 60; ++k) {
    const DualFrequencyObservation obs = sim.observe(5, k * 1.0, k);
    const SatelliteArcStatus st = tracker.process(kT0 + k * 1.0, {obs}).satellites.at(0);
    ASSERT_EQ(st.phase1_cycles, obs.phase1_cycles);
    ASSERT_EQ(st.phase2_cycles, obs.phase2_cycles);
  }
  for (int k = kBack; k < kBack + 2; ++k) {
    const DualFrequencyObservation obs = sim.observe(5, k * 1.0, k);
    const SatelliteArcStatus st = tracker.process(kT0 + k * 1.0, {obs}).satellites.at(0);
    ASSERT_EQ(st.phase_correction1_cycles, 3) << "epoch " << k;
    ASSERT_EQ(st.phase_correction2_cycles, -2) << "epoch " << k;
    EXPECT_EQ(st.phase1_cycles, obs.phase1_cycles - 3.0) << "epoch " << k;
    EXPECT_EQ(st.phase2_cycles, obs.phase2_cycles + 2.0) << "epoch " << k;
  }
  const DualFrequencyObservation obs = sim.observe(5, kBack + 2.0, kBack + 2);
  const SatelliteArcStatus restarted = tracker.process(kT0 + (kBack + 2) * 1.0, {obs}).satellites.at(0);
  EXPECT_TRUE(restarted.new_arc);
  EXPECT_EQ(restarted.phase_correction1_cycles, 0);
  EXPECT_EQ(restarted.phase1_cycles, obs.phase1_cycles);
  EXPECT_EQ(restarted.phase2_cycles, obs.phase2_cycles);
}

TEST(ArcTracker, BadEpochsAreRefusedWithoutStateChange) {
  Simulator sim(5);
  ArcTracker tracker;
  std::vector<DualFrequencyObservation> obs{sim.observe(5, 0.0, 0)};
  EXPECT_TRUE(tracker.process(kT0, obs).accepted);
  obs = {sim.observe(5, 30.0, 1)};
  EXPECT_TRUE(tracker.process(kT0 + 30.0, obs).accepted);
  auto r = tracker.process(kT0 + 30.0, obs);
  EXPECT_FALSE(r.accepted);
  EXPECT_EQ(r.refusal_reason.rfind("duplicate epoch", 0), 0u) << r.refusal_reason;
  r = tracker.process(kT0, obs);
  EXPECT_FALSE(r.accepted);
  EXPECT_EQ(r.refusal_reason.rfind("time goes backwards by 30.000 s", 0), 0u) << r.refusal_reason;
  // Non-finite values and a repeated satellite are unusable, never a crash.
  auto bad = sim.observe(7, 60.0, 2);
  bad.code1_m = std::nan("");
  obs = {sim.observe(5, 60.0, 2), bad, sim.observe(5, 60.0, 2)};
  r = tracker.process(kT0 + 60.0, obs);
  ASSERT_TRUE(r.accepted);
  EXPECT_TRUE(r.satellites[0].usable);
  EXPECT_FALSE(r.satellites[0].new_arc);
  EXPECT_FALSE(r.satellites[1].usable);
  EXPECT_EQ(r.satellites[1].arc, 0u);
  EXPECT_FALSE(r.satellites[2].usable);
}

// ---------------------------------------------------------------- real data

struct RealEpoch {
  GnssTime time;
  std::vector<DualFrequencyObservation> obs;
};

/// GPS C1C/C2W/L1C/L2W of a RINEX file as DualFrequencyObservation.
std::vector<RealEpoch> readGpsL1L2(const std::string& path) {
  auto reader = RinexObsReader::open(path);
  const auto c1 = *ObservationCode::parse("C1C"), c2 = *ObservationCode::parse("C2W");
  const auto l1 = *ObservationCode::parse("L1C"), l2 = *ObservationCode::parse("L2W");
  std::vector<RealEpoch> out;
  ObsEpoch e;
  while (reader.next(e)) {
    RealEpoch re{e.time, {}};
    for (const auto& so : e.satellites) {
      if (so.satellite.system != GnssSystem::GPS) continue;
      const auto *p1 = e.find(so.satellite, c1), *p2 = e.find(so.satellite, c2);
      const auto *q1 = e.find(so.satellite, l1), *q2 = e.find(so.satellite, l2);
      if (!p1 || !p2 || !q1 || !q2 || !p1->value || !p2->value || !q1->value || !q2->value) continue;
      DualFrequencyObservation o;
      o.satellite = so.satellite;
      o.time = e.time;
      o.code1 = c1, o.code2 = c2, o.phase1 = l1, o.phase2 = l2;
      o.frequency1_hz = kF1, o.frequency2_hz = kF2;
      o.code1_m = *p1->value, o.code2_m = *p2->value;
      o.phase1_cycles = *q1->value, o.phase2_cycles = *q2->value;
      o.loss_of_lock1 = q1->lli && (*q1->lli & 1);
      o.loss_of_lock2 = q2->lli && (*q2->lli & 1);
      re.obs.push_back(o);
    }
    out.push_back(std::move(re));
  }
  return out;
}

struct RealRun {
  std::size_t epochs = 0, satellites_seen = 0, slips = 0, lli = 0;
  std::vector<std::string> slip_texts;
  std::set<std::pair<std::size_t, SatelliteId>> detections;  // (epoch, sat) of every slip
};

RealRun runReal(const std::vector<RealEpoch>& data) {
  ArcTracker tracker;
  RealRun run;
  std::set<SatelliteId> seen;
  for (std::size_t k = 0; k < data.size(); ++k) {
    const auto r = tracker.process(data[k].time, data[k].obs);
    EXPECT_TRUE(r.accepted);
    ++run.epochs;
    for (const auto& s : r.satellites) {
      seen.insert(s.satellite);
      if (s.new_arc && s.start_reason == ArcStartReason::LossOfLock) ++run.lli;
      if (s.new_arc && s.start_reason != ArcStartReason::NewSatellite) {
        ++run.slips;
        run.detections.insert({k, s.satellite});
        run.slip_texts.push_back(data[k].time.toString(TimeSystem::GPS, 0) + " " + s.satellite.toString() + ": " +
                                 s.reason);
      }
    }
  }
  run.satellites_seen = seen.size();
  return run;
}

/// Adds (dn1, dn2) cycles to a satellite's phases from epoch `from` on.
void injectSlip(std::vector<RealEpoch>& data, const SatelliteId& sat, std::size_t from, int dn1, int dn2) {
  for (std::size_t k = from; k < data.size(); ++k)
    for (auto& o : data[k].obs)
      if (o.satellite == sat) o.phase1_cycles += dn1, o.phase2_cycles += dn2;
}

/// Satellites observed in every epoch (continuous over the hour).
std::vector<SatelliteId> continuousSatellites(const std::vector<RealEpoch>& data) {
  std::map<SatelliteId, std::size_t> count;
  for (const auto& e : data)
    for (const auto& o : e.obs) ++count[o.satellite];
  std::vector<SatelliteId> out;
  for (const auto& [sat, n] : count)
    if (n == data.size()) out.push_back(sat);
  return out;
}

void checkRealFile(const std::string& relative, std::size_t expected_lli_breaks) {
  auto data = readGpsL1L2(ppp::test::dataPath(relative));
  ASSERT_EQ(data.size(), 120u);  // one hour at 30 s (data README)
  const auto clean = runReal(data);
  std::string list;
  for (const auto& s : clean.slip_texts) list += "\n  " + s;
  std::cout << relative << ": " << clean.satellites_seen << " GPS satellites, " << clean.slips
            << " arc breaks on the clean data, " << clean.lli << " of them receiver LLI flags" << list << "\n";
  // Breaks not flagged by the receiver are false slips of our detectors.
  EXPECT_EQ(clean.slips - clean.lli, 0u) << list;
  EXPECT_EQ(clean.lli, expected_lli_breaks) << list;

  // Inject slips into continuous satellites, at known epochs.
  const auto sats = continuousSatellites(data);
  ASSERT_GE(sats.size(), 5u);
  const std::vector<std::tuple<std::size_t, int, int>> slips = {
      {20, 1, 0}, {35, 0, 1}, {50, 1, 1}, {65, 9, 7}, {80, 3, -2}, {95, -2, -2}, {110, 5, 3}};
  std::set<std::pair<std::size_t, SatelliteId>> expected;
  for (std::size_t i = 0; i < slips.size(); ++i) {
    const auto& [epoch, dn1, dn2] = slips[i];
    const auto sat = sats[i % sats.size()];
    injectSlip(data, sat, epoch, dn1, dn2);
    expected.insert({epoch, sat});
  }
  const auto slipped = runReal(data);
  for (const auto& e : expected)
    EXPECT_EQ(slipped.detections.count(e), 1u)
        << relative << ": slip on " << e.second.toString() << " at epoch " << e.first << " not detected";
  // Nothing else beyond what the clean data already had.
  EXPECT_LE(slipped.slips, clean.slips + expected.size());
}

TEST(ArcTrackerRealData, Zim2CleanAndInjectedSlips) {
  PPP_REQUIRE_SHARED_DATA();
    // 4 epochs with LLI bit 0 on L1C/L2W within arcs in the file (G30 00:12:30, 00:14:30; G25 00:57:30, 00:58:30).
  checkRealFile("zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx", 4);
}

TEST(ArcTrackerRealData, Ccj2CleanAndInjectedSlips) {
  PPP_REQUIRE_SHARED_DATA();
    // 7 epochs with LLI bit 0 within arcs in the file (G17 once, G27 five times, G30 once).
  checkRealFile("ccj2-2021-210/ccj22100.21o", 7);
}

}  // namespace
}  // namespace ppp
