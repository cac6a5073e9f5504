// "UBX walk": gnss_1730.ubx positioned on its own, with the broadcast
// ephemerides decoded from its RXM-SFRBX (GPS LNAV, Galileo I/NAV), by the
// broadcast single-point solution (ppp/pipeline/broadcast_single_point.h: dual-frequency
// ionosphere-free code, so no ionosphere model), compared epoch by epoch with
// the RTK-fixed reference gnss_1730_sf.pos (cm level; ../shared/data/streams
// README). Reported per epoch rate: all 4 Hz epochs, and decimated to 1 Hz (the
// first epoch of each second). The IF code is carrier-smoothed (Hatch).
// And the PPP chain (ppp_solve --ubx F --nav F) on the recording alone: no
// approximate position, the estimators start on their own (start model), and
// the broadcast-only solution against the same reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "ppp_bayes_tree/evaluation/rtklib_pos.h"
#include "ppp_bayes_tree/io/imu/imu_file_loader.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/broadcast_single_point.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/navigation/imu_noise.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "test_support.h"

namespace ppp {
namespace {

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const std::size_t k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1;
  return v[std::min(k, v.size() - 1)];
}

/// The geoid undulation the receiver used: NAV-PVT height - hMSL of the first NAV-PVT
/// (interface description UBX-NAV-PVT: height above ellipsoid at byte 32, above mean sea
/// level at 36, mm); nullopt without a NAV-PVT.
std::optional<double> navPvtGeoidUndulation_m(const std::string& ubx) {
  UbxFramer framer;
  const std::string bytes = test::readFileBytes(ubx);
  std::optional<double> undulation_m;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), [&](const UbxFrame& f) {
    if (undulation_m || f.messageType() != 0x0107 || f.payload.size() < 40) return;
    auto i4 = [&](std::size_t at) {
      return static_cast<std::int32_t>(f.payload[at] | (f.payload[at + 1] << 8) | (f.payload[at + 2] << 16) |
                                       (static_cast<std::uint32_t>(f.payload[at + 3]) << 24));
    };
    undulation_m = (i4(32) - i4(36)) * 1e-3;
  });
  return undulation_m;
}

/// The reference position (ECEF, ellipsoidal height) of the reference epoch nearest to `t`
/// within 0.1 s (the reference tags are 1 ms later than the receiver's); its heights are above
/// the geoid (they equal NAV-PVT hMSL): back to the ellipsoid with the receiver's undulation.
std::optional<Eigen::Vector3d> referenceEcef(const PosFile& reference, const GnssTime& t, double undulation_m) {
  const PosRecord* ref = nullptr;
  double best = 0.1;
  for (const auto& r : reference.records) {
    const double dt = std::abs(r.time - t);
    if (dt < best) {
      best = dt;
      ref = &r;
    }
  }
  if (!ref) return std::nullopt;
  Geodetic geo = ecefToGeodetic(ref->position_ecef_m);
  geo.height_m += undulation_m;
  return geodeticToEcef(geo);
}

/// Why the walk's recording or reference is missing; nullopt when both are there.
std::optional<std::string> missingWalkData() {
  if (std::filesystem::exists(test::dataPath("streams/ubx/gnss_1730.ubx")) &&
      std::filesystem::exists(test::dataPath("streams/ubx/gnss_1730_sf.pos")))
    return std::nullopt;
  return "UBX walk data not found under " + test::dataPath("streams/ubx");
}

/// Per-component median.
Eigen::Vector3d medianOf(const std::vector<Eigen::Vector3d>& v) {
  Eigen::Vector3d m;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> c;
    for (const auto& o : v) c.push_back(o(k));
    m(k) = percentile(c, 0.5);
  }
  return m;
}

/// The configuration of the live rostest on the walk (config/live.yaml + test/rostest/live_ubx.yaml).
PppConfig walkConfig() {
  const std::string repo = PPP_REPO_DIR;
  return loadPppConfig(std::vector<std::string>{repo + "/config/live.yaml", repo + "/test/rostest/live_ubx.yaml"});
}

/// ppp_solve --ubx UBX --nav UBX --atx (the trimmed satellite ANTEX).
PppInputFiles walkFiles(const std::string& ubx) {
  PppInputFiles files;
  files.obs = ubx;
  files.obs_format = ObservationFormat::Ubx;
  files.nav = {ubx};
  files.atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx")};
  return files;
}

/// The walk's GNSS/INS options of doc/studies/ins_walk.md: consumer grade, lever arm 0,-0.05,0.
void setWalkIns(PppConfig& config) {
  config.ins.noise = imuNoisePreset(ImuGrade::ConsumerMems);
  config.ins.lever_arm_body_m = Eigen::Vector3d(0.0, -0.05, 0.0);
}

/// The walk's IMU readings (imu_1730.csv with its time tags), turned into the body axes by
/// `rotation_body_imu` (the data set's mounting: rotationNedBody(pi, 0, -pi/2)).
std::vector<ImuSample> walkImu(const Eigen::Matrix3d& rotation_body_imu) {
  ImuFileOptions imu;
  imu.path = test::dataPath("streams/ubx/imu_1730.csv");
  imu.tag_path = imu.path + ".tag";
  imu.format = ImuFileFormat::RtklibLogged;
  imu.rotation_body_imu = rotation_body_imu;
  return loadImuFile(imu).samples;
}

TEST(UbxWalk, BroadcastSinglePointAgainstTheRtkReference) {
  const std::string ubx = test::dataPath("streams/ubx/gnss_1730.ubx");
  const std::string pos = test::dataPath("streams/ubx/gnss_1730_sf.pos");
  if (!std::filesystem::exists(ubx) || !std::filesystem::exists(pos))
    GTEST_SKIP() << "UBX walk data not found under " << test::dataPath("streams/ubx");
  UbxDecoderOptions decoding;
  decoding.max_phase_stdev_index = 15;  // every valid phase, for the carrier smoothing
  UbxObservationSource source(ubx, decoding);
  BroadcastEphemerisStore store;
  for (const auto& e : source.navigation().gps) EXPECT_FALSE(store.add(e).has_value());
  for (const auto& e : source.navigation().galileo) EXPECT_FALSE(store.add(e).has_value());
  const PosFile reference = readRtklibPos(pos);
  ASSERT_GT(reference.records.size(), 500u);

  const std::optional<double> undulation = navPvtGeoidUndulation_m(ubx);
  ASSERT_TRUE(undulation) << "no NAV-PVT in the recording";
  const double undulation_m = *undulation;
  std::vector<double> errors_4hz, errors_1hz;
  std::vector<Eigen::Vector3d> offsets_enu;
  std::vector<GnssTime> solved_times;
  std::map<GnssSystem, std::vector<double>> residuals;
  std::optional<Eigen::Vector3d> previous;
  IonosphereFreeCodeSmoother smoother;  // 100 epochs (25 s); longer windows change the median by < 0.3 m
  std::size_t epochs = 0, solved = 0;
  std::int64_t last_second = -1;
  std::string first_reason;
  ObsEpoch epoch;
  while (source.next(epoch) == ObservationRead::Epoch) {
    ++epochs;
    const auto smoothed = smoother.update(epoch);
    const auto sol = broadcastSinglePoint(epoch, store, previous, {}, &smoothed);
    if (!sol.ok) {
      if (first_reason.empty()) first_reason = epoch.time.toString() + ": " + sol.reason;
      continue;
    }
    ++solved;
    previous = sol.position_ecef_m;
    for (std::size_t i = 0; i < sol.used.size(); ++i) residuals[sol.used[i].system].push_back(sol.residuals_m[i]);
    const std::optional<Eigen::Vector3d> ref = referenceEcef(reference, epoch.time, undulation_m);
    if (!ref) continue;
    const Eigen::Vector3d& reference_ecef = *ref;
    const double error = (sol.position_ecef_m - reference_ecef).norm();
    solved_times.push_back(epoch.time);
    errors_4hz.push_back(error);
    offsets_enu.push_back(ecefToEnu(sol.position_ecef_m, reference_ecef));
    const std::int64_t second = static_cast<std::int64_t>(std::floor(epoch.time.toGpsSecondsDouble() + 0.01));
    if (second != last_second) {
      errors_1hz.push_back(error);
      last_second = second;
    }
  }
  ASSERT_FALSE(errors_4hz.empty()) << first_reason;
  std::printf("UBX walk, broadcast SPP (IF code, GPS+Galileo, SFRBX ephemerides: %zu GPS, %zu Galileo)\n",
              source.navigation().gps.size(), source.navigation().galileo.size());
  std::printf("  epochs %zu, solved %zu (before the first ephemerides: %s)\n", epochs, solved, first_reason.c_str());
  std::printf("  4 Hz: %zu epochs, 3D error median %.2f m, p95 %.2f m, max %.2f m\n", errors_4hz.size(),
              percentile(errors_4hz, 0.5), percentile(errors_4hz, 0.95), percentile(errors_4hz, 1.0));
  std::printf("  1 Hz: %zu epochs, 3D error median %.2f m, p95 %.2f m, max %.2f m\n", errors_1hz.size(),
              percentile(errors_1hz, 0.5), percentile(errors_1hz, 0.95), percentile(errors_1hz, 1.0));
  for (const auto& [system, r] : residuals) {
    double ss = 0.0;
    for (double v : r) ss += v * v;
    const double rms = std::sqrt(ss / static_cast<double>(r.size()));
    std::printf("  %s IF code residual RMS %.2f m over %zu\n", std::string(systemName(system)).c_str(), rms, r.size());
    EXPECT_LT(rms, 5.0) << systemName(system);  // metre level: a wrong record would show as tens of metres
  }
  // The constant part of the difference (median ENU offset) and the rest: the walk's shape.
  const Eigen::Vector3d median_offset = medianOf(offsets_enu);
  std::vector<double> shape_4hz, shape_1hz;
  std::int64_t shape_second = -1;
  for (std::size_t i = 0; i < offsets_enu.size(); ++i) {
    const double e = (offsets_enu[i] - median_offset).norm();
    shape_4hz.push_back(e);
    const std::int64_t second = static_cast<std::int64_t>(std::floor(solved_times[i].toGpsSecondsDouble() + 0.01));
    if (second != shape_second) {
      shape_1hz.push_back(e);
      shape_second = second;
    }
  }
  std::printf("  geoid undulation from NAV-PVT %.3f m; median ENU offset from the reference %.2f %.2f %.2f m\n",
              undulation_m, median_offset.x(), median_offset.y(), median_offset.z());
  std::printf("  offset removed: 4 Hz median %.2f m p95 %.2f m; 1 Hz median %.2f m p95 %.2f m\n",
              percentile(shape_4hz, 0.5), percentile(shape_4hz, 0.95), percentile(shape_1hz, 0.5),
              percentile(shape_1hz, 0.95));
  // NOT the target (median 3D below 3 m): at the time of writing 8.7 m (4 Hz)
  // and 8.6 m (1 Hz). Two parts, both measured: (1) a constant one, median ENU offset
  // (6.0, 2.6, -1.9) m; RTKLIB's own broadcast single point on convbin's RINEX of this
  // file (rnx2rtkp single, dual-frequency, Saastamoinen) sits 13 m east of the
  // reference too, so part of it looks like the reference's absolute datum (an RTK
  // solution relative to a base; its heights are above the geoid); (2) scatter, 5.4 m
  // median with the offset removed: the IF code of a walking patch antenna (multipath
  // tripled by the IF combination, not removed by carrier smoothing; this file has no
  // GPS Klobuchar page for a single-frequency solution). An experiment with L1 code
  // and an arc-mean ionosphere from the IF difference (non-causal) took the scatter
  // to 3.1 m but left the offset: median 7.0 m. The bounds below hold the figures
  // with a margin.
  EXPECT_LT(percentile(errors_4hz, 0.5), 12.0);
  EXPECT_LT(percentile(errors_1hz, 0.5), 12.0);
  EXPECT_LT(percentile(shape_4hz, 0.5), 8.0);
  EXPECT_LT(percentile(shape_1hz, 0.5), 8.0);
  EXPECT_GT(solved, epochs / 2);
}


TEST(UbxWalk, PppWithoutApproximatePositionStartsOnItsOwn) {
  // The PPP chain on the recording alone (ppp_solve --ubx F --nav F with the live rostest's
  // configuration: config/live.yaml + test/rostest/live_ubx.yaml, GPS + Galileo,
  // broadcast-only): a UBX file carries no station position, so each estimator starts from
  // the Earth centre on the start model (PppEstimator step 1) once four satellites of
  // the run have an ephemeris received before the epoch (11 records in 2 min).
  PPP_REQUIRE_SHARED_DATA();
  const std::string ubx = test::dataPath("streams/ubx/gnss_1730.ubx");
  const std::string pos = test::dataPath("streams/ubx/gnss_1730_sf.pos");
  if (!std::filesystem::exists(ubx) || !std::filesystem::exists(pos))
    GTEST_SKIP() << "UBX walk data not found under " << test::dataPath("streams/ubx");
  const PppConfig config = walkConfig();
  ASSERT_EQ(config.signals.systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo}));
  const PppInputFiles files = walkFiles(ubx);
  const PosFile reference = readRtklibPos(pos);
  const std::optional<double> undulation = navPvtGeoidUndulation_m(ubx);
  ASSERT_TRUE(undulation) << "no NAV-PVT in the recording";
  const double undulation_m = *undulation;

  for (const std::string name : {"ekf", "smoother"}) {
    PppPipeline pipeline(files, config);
    std::string why;
    auto estimator = makeEstimator(name, config, &why);
    ASSERT_TRUE(estimator) << why;
    std::optional<GnssTime> first_solved;
    std::size_t unstarted_named = 0, before_first = 0;
    std::vector<std::pair<GnssTime, Eigen::Vector3d>> solved;
    const PppRunSummary summary = pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
      if (rec.status == EpochStatus::Ok && rec.solution.position_ecef_m) {
        if (!first_solved) first_solved = rec.solution.time;
        solved.emplace_back(rec.solution.time, *rec.solution.position_ecef_m);
        return;
      }
      if (first_solved) return;
      ++before_first;
      // Before the first solution: no start yet, with the start model's reason.
      EXPECT_EQ(rec.no_solution_reason, NoSolutionReason::NoInitialPosition) << rec.reason;
      if (rec.reason.find("no initial position: no approximate position, start model from the Earth centre: ") == 0)
        ++unstarted_named;
    });
    ASSERT_TRUE(first_solved) << name;
    EXPECT_EQ(summary.epochs_read, 536u);  // RXM-RAWX epochs (data README)
    EXPECT_EQ(unstarted_named, before_first);
    EXPECT_EQ(summary.no_solution_counts.at(NoSolutionReason::NoInitialPosition), before_first);
    EXPECT_LT(*first_solved - test::gpst(2025, 8, 28, 17, 30, 39.0), 60.0);  // the first minute waits for records
    std::vector<double> errors;
    std::vector<Eigen::Vector3d> offsets_enu;
    for (const auto& [t, x] : solved)
      if (const auto ref = referenceEcef(reference, t, undulation_m)) {
        errors.push_back((x - *ref).norm());
        offsets_enu.push_back(ecefToEnu(x, *ref));
      }
    const Eigen::Vector3d median_offset = medianOf(offsets_enu);
    std::vector<double> shape;
    for (const auto& o : offsets_enu) shape.push_back((o - median_offset).norm());
    std::printf("UBX walk, broadcast-only PPP (%s, no approximate position): %zu epochs, %zu solved (first at %s, %zu "
                "waiting for ephemerides before), 3D error to the reference median %.2f m, p95 %.2f m, max %.2f m; "
                "median ENU offset %.2f %.2f %.2f m; offset removed median %.2f m, p95 %.2f m\n",
                name.c_str(), summary.epochs_read, summary.epochs_solved, first_solved->toString().c_str(), before_first,
                percentile(errors, 0.5), percentile(errors, 0.95), percentile(errors, 1.0), median_offset.x(),
                median_offset.y(), median_offset.z(), percentile(shape, 0.5), percentile(shape, 0.95));
    // At the time of writing (EKF and smoother filtered alike): 338 of 536 epochs solved
    // (the first at 17:31:25.25, 46 s in), 3D error median 9.62 m, p95 13.6 m, max 14.3 m;
    // median ENU offset (6.6, 3.5, -3.6) m, the constant part the broadcast single point
    // above shows too (6.0, 2.6, -1.9 m: the reference's absolute datum and the broadcast
    // orbits and clocks); with it removed median 3.2 m, p95 14.1 m: the height moves by
    // up to 13 m over the last 15 s as satellites join (8-9 used instead of 5-7), the
    // broadcast errors of a 2-minute float solution with few satellites.
    EXPECT_GE(summary.epochs_solved, 300u);
    EXPECT_EQ(errors.size(), solved.size());
    EXPECT_LT(percentile(errors, 0.5), 12.0);
    EXPECT_LT(percentile(shape, 0.5), 4.0);
  }
}


TEST(UbxWalk, PipelineReadsAUbxRecordingAsItsObservations) {
  // ppp_solve --ubx: PppInputFiles with obs_format Ubx. The shared data hold no precise
  // products of 2025-08-28, so with the ZIM2 products the pipeline must stop with the
  // UBX file's own observation window in the message (proof that it was decoded).
  PPP_REQUIRE_SHARED_DATA();
  const std::string ubx = test::dataPath("streams/ubx/gnss_1730.ubx");
  if (!std::filesystem::exists(ubx)) GTEST_SKIP() << "UBX recording not found at " << ubx;
  PppInputFiles files;
  files.obs = ubx;
  files.obs_format = ObservationFormat::Ubx;
  files.sp3 = {test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3")};
  files.clk = {test::dataPath("zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK")};
  files.atx = {test::dataPath("antex/igs20_zim2_gps_trim.atx")};
  try {
    PppPipeline pipeline(files, PppConfig{});
    FAIL() << "products of 2026 accepted for a 2025 recording";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("2025-08-28 17:30:40"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ppp

namespace ppp {

TEST(UbxWalk, EkfInsStartRefusedInMotionEndsBridgedArcsWithoutACrash) {
  // The walk's first solution comes in motion: with a heading given, ekf_ins levels the
  // readings up to each start attempt and refuses (too few, not at rest), epoch after
  // epoch. Arcs bridged over a gap in those epochs reach a start attempt, which has no
  // state from before the gap: they end (no gap covariance from an empty filter).
  PPP_REQUIRE_SHARED_DATA();
  const std::string ubx = test::dataPath("streams/ubx/gnss_1730.ubx");
  PppConfig config = walkConfig();
  config.ins.initial_heading_rad = -42.8 * kDegToRad;
  setWalkIns(config);
  PppPipeline pipeline(walkFiles(ubx), config);
  pipeline.setImu(walkImu(rotationNedBody(M_PI, 0.0, -M_PI / 2.0)));  // doc/studies/ins_walk.md
  std::string why;
  auto estimator = makeEstimator("ekf_ins", config, &why);
  ASSERT_TRUE(estimator) << why;
  std::size_t epochs = 0, no_attitude = 0;
  pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    ++epochs;
    no_attitude += rec.no_solution_reason == NoSolutionReason::NoInitialAttitude;
  });
  std::printf("[ figures  ] %zu epochs, %zu without an initial attitude\n", epochs, no_attitude);
  EXPECT_EQ(epochs, 536u);
  EXPECT_GT(no_attitude, 300u);  // every epoch with a start position (the 182 before have none)
}


TEST(UbxWalk, SmootherInsAgreesWithItselfOnARoundingLevelChangeOfTheMounting) {
  // smoother_ins as in doc/studies/ins_walk.md (no attitude given: levelled at the start, the
  // heading aligned in motion), run twice: the IMU's mounting given as roll 180 and as roll
  // -180 deg, the same mounting, the rotation matrices differing at the rounding level
  // (sin(-pi) = -sin(pi)). Its information matrix is ill conditioned (ppp_ins_smoother.h
  // "Numerics"): with the cliques factorized by Cholesky the two runs parted by 8 mm at the
  // ninth solution and by 54 m within these epochs; by QR they agree to micrometres. The walk's
  // first 27 s of solutions (to 17:31:52), through its worst geometry (5 satellites, 17:31:44 on).
  PPP_REQUIRE_SHARED_DATA();
  if (const auto missing = missingWalkData()) GTEST_SKIP() << *missing;
  const std::string ubx = test::dataPath("streams/ubx/gnss_1730.ubx");
  const std::string pos = test::dataPath("streams/ubx/gnss_1730_sf.pos");
  PppConfig config = walkConfig();
  setWalkIns(config);
  PppInputFiles files = walkFiles(ubx);
  files.window.end = test::gpst(2025, 8, 28, 17, 31, 52.0);
  const auto solve = [&](const Eigen::Matrix3d& rotation_body_imu) {
    PppPipeline pipeline(files, config);
    pipeline.setImu(walkImu(rotation_body_imu));
    std::string why;
    auto estimator = makeEstimator("smoother_ins", config, &why);
    EXPECT_TRUE(estimator) << why;
    std::vector<std::pair<GnssTime, Eigen::Vector3d>> solved;
    if (!estimator) return solved;
    pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
      if (rec.status == EpochStatus::Ok && rec.solution.position_ecef_m)
        solved.emplace_back(rec.solution.time, *rec.solution.position_ecef_m);
    });
    return solved;
  };
  const Eigen::Matrix3d mounting = rotationNedBody(M_PI, 0.0, -M_PI / 2.0);  // doc/studies/ins_walk.md
  const Eigen::Matrix3d twin = rotationNedBody(-M_PI, 0.0, -M_PI / 2.0);
  ASSERT_NE(mounting, twin);  // a change at the rounding level, not none
  ASSERT_LT((mounting - twin).cwiseAbs().maxCoeff(), 1e-15);
  const auto a = solve(mounting);
  const auto b = solve(twin);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 100u);  // 108 when written (the first at 17:31:25.25)
  const PosFile reference = readRtklibPos(pos);
  const std::optional<double> undulation = navPvtGeoidUndulation_m(ubx);
  ASSERT_TRUE(undulation) << "no NAV-PVT in the recording";
  double apart_m = 0.0;
  std::vector<double> errors;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].first, b[k].first) << k;
    apart_m = std::max(apart_m, (a[k].second - b[k].second).norm());
    if (const auto ref = referenceEcef(reference, a[k].first, *undulation)) errors.push_back((a[k].second - *ref).norm());
  }
  ASSERT_EQ(errors.size(), a.size());
  std::printf("[ figures  ] smoother_ins, %zu solutions: the two mountings %.3g m apart at most; 3D error to the "
              "reference median %.2f m, max %.2f m\n",
              a.size(), apart_m, percentile(errors, 0.5), percentile(errors, 1.0));
  EXPECT_LT(apart_m, 0.01);  // 5e-6 m when written
  // Against the reference, when written: median 8.6 m, max 42.9 m at the weak geometry
  // (17:31:44-17:31:52, 5-6 satellites). ppp_solve over the same epochs: the GNSS-only
  // smoother 8.8 m and 43.1 m, ekf_ins 7.3 m and 39.0 m. The max is the GNSS's: since the
  // adaptive process noise (ins_process_noise_adaptation.h) smoother_ins follows the phases
  // there as the GNSS-only smoother does (before it: 8.4 m and 32.0 m here, but 15-30 m
  // off for the minute after, doc/studies/ins_walk.md). The bound holds the GNSS-only
  // smoother's excursion with a margin and fails on a diverging twin (smoother_ins by
  // Cholesky: 8.3 m and 44.5 m, 8.2 m and 81.3 m with the other mounting).
  EXPECT_LT(percentile(errors, 0.5), 12.0);
  EXPECT_LT(percentile(errors, 1.0), 50.0);
}

TEST(UbxWalk, InsEstimatorsLeaveTheWeakGeometryAsTheGnssOnlySmootherDoes) {
  // ekf_ins and smoother_ins over the whole walk as in doc/studies/ins_walk.md (no attitude
  // given; consumer grade). From 17:31:44 five or six satellites, all high, leave the
  // position against the white receiver clocks weak: every estimator moves tens of metres
  // up and west there (the GNSS-only smoother 43 m). The GNSS-only estimators are back
  // within metres by 17:31:56. Without the adaptive process noise the INS estimators stayed
  // off until about 17:32:40: their confidently wrong predictions had the postfit test
  // reject the phases of right satellites (ekf_ins 191, smoother_ins 126), and the update
  // turned the rest into metre-sized steps along the weak direction, which the code pulled
  // back only slowly. 3D error to the reference over 17:32:00-17:32:40, median and max:
  // ekf_ins 23.3 m and 37.5 m, smoother_ins 13.2 m and 21.5 m then; 5.7 m and 10.4 m, 5.2 m
  // and 7.3 m with the adaptation alone, 9.3 m and 11.1 m, 6.7 m and 9.5 m with the gyro bias
  // taken from the levelling too (the GNSS-only smoother 6.0 m and 8.9 m). Over the walk:
  // median 17.8 and 11.1 m then, 5.8 and 5.7 m, then 8.7 and 7.0 m (GNSS-only smoother
  // 7.7 m). The bounds sit between: twice the GNSS-only smoother's median over the minute
  // after, and its median over the walk with a margin. Without the adaptation (the gyro
  // bias taken) 21.6 m and 12.3 m over the minute after: both fail.
  PPP_REQUIRE_SHARED_DATA();
  if (const auto missing = missingWalkData()) GTEST_SKIP() << *missing;
  const std::string ubx = test::dataPath("streams/ubx/gnss_1730.ubx");
  PppConfig config = walkConfig();
  setWalkIns(config);
  const PosFile reference = readRtklibPos(test::dataPath("streams/ubx/gnss_1730_sf.pos"));
  const std::optional<double> undulation = navPvtGeoidUndulation_m(ubx);
  ASSERT_TRUE(undulation) << "no NAV-PVT in the recording";
  const std::vector<ImuSample> readings = walkImu(rotationNedBody(M_PI, 0.0, -M_PI / 2.0));
  const GnssTime from = test::gpst(2025, 8, 28, 17, 32, 0.0), to = test::gpst(2025, 8, 28, 17, 32, 40.0);
  for (const std::string name : {"ekf_ins", "smoother_ins"}) {
    PppPipeline pipeline(walkFiles(ubx), config);
    pipeline.setImu(readings);
    std::string why;
    auto estimator = makeEstimator(name, config, &why);
    ASSERT_TRUE(estimator) << why;
    std::vector<double> walk, after;
    pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
      if (rec.status != EpochStatus::Ok || !rec.solution.position_ecef_m) return;
      const std::optional<Eigen::Vector3d> ref = referenceEcef(reference, rec.solution.time, *undulation);
      if (!ref) return;
      const double error_m = (*rec.solution.position_ecef_m - *ref).norm();
      walk.push_back(error_m);
      if (rec.solution.time - from >= 0.0 && to - rec.solution.time >= 0.0) after.push_back(error_m);
    });
    ASSERT_GT(walk.size(), 300u) << name;  // 337 and 338 of 536 epochs when written
    ASSERT_GT(after.size(), 100u) << name;
    std::printf("[ figures  ] %s: %zu solutions, 3D error median %.2f m over the walk; over 17:32:00-17:32:40 median "
                "%.2f m, max %.2f m\n",
                name.c_str(), walk.size(), percentile(walk, 0.5), percentile(after, 0.5), percentile(after, 1.0));
    EXPECT_LT(percentile(walk, 0.5), 10.0) << name;
    EXPECT_LT(percentile(after, 0.5), 12.0) << name;
    EXPECT_LT(percentile(after, 1.0), 15.0) << name;
  }
}

}  // namespace ppp
