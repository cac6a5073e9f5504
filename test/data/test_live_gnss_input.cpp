// LiveGnssInput (app/live_gnss_input.h): byte chunks of receiver and
// correction streams in, epochs and one live ephemeris out; the PPP on them
// must equal ppp_solve's on the same recordings (the nodes' 1 mm promise).
//  a) ESBC 2020-177, 45 min: the RINEX observations made into an MSM7 stream
//     by ppp_stream_make's builder (app/caster_stream_builder.h),
//     the GRG SP3/CLK made into an SSR stream against the station's broadcast
//     file (ppp_ssr_encode's core), both cut into random chunks and fed
//     interleaved in arrival order; EKF and smoother epoch by epoch against
//     the batch run (ppp_solve --rtcm OBS --nav NAV --ssr SSR's pipeline).
//  b) A real recording with ephemerides in the stream (STR2, week rollover):
//     broadcast-only PPP through LiveGnssInput against ppp_solve --rtcm X --nav X.
//  c) Degraded: an SSR outage (broadcast-only with wider covariance, then
//     back), garbage and a CRC error in the observation stream (counted; the
//     epochs before it unchanged), time going backwards (counted, dropped).
//  d) A u-blox UBX recording (RXM-RAWX + RXM-SFRBX, no station position: the
//     estimators start on the start model): EKF and smoother filtered against
//     ppp_solve --ubx X --nav X epoch by epoch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <random>

#include "ppp_bayes_tree/app/live_gnss_input.h"
#include "ppp_bayes_tree/app/caster_stream_builder.h"
#include "ppp_bayes_tree/io/epoch_time_screen.h"
#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/io/transport/file_replay_source.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"
#include "ppp_bayes_tree/models/broadcast_products.h"
#include "ppp_bayes_tree/models/ssr_broadcast_fallback.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/ssr_from_precise.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "test_support.h"
#include "window_observation_source.h"

namespace ppp {
namespace {

std::string esbc(const std::string& file) { return test::dataPath("esbc-2020-177/" + file); }

std::vector<std::uint8_t> concat(const std::vector<TimedFrame>& frames) {
  std::vector<std::uint8_t> all;
  for (const auto& f : frames) all.insert(all.end(), f.bytes.begin(), f.bytes.end());
  return all;
}

void writeFile(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// The ESBC window as streams: observations (MSM7, arriving 0.5 s after their
/// epoch) and SSR (GPS, 5 s, centre of mass, arriving 2 s after their epoch).
struct EsbcStreams {
  GnssTime start, until;
  std::vector<TimedFrame> obs, ssr;
  std::string dir, obs_path, ssr_path, nav_path;
  std::vector<std::string> atx;
};

const EsbcStreams& esbcStreams() {
  static const EsbcStreams streams = [] {
    EsbcStreams s;
    s.start = test::gpst(2020, 6, 25, 0, 0, 0);
    s.until = test::gpst(2020, 6, 25, 0, 45, 0);
    s.dir = test::tempDir("live_esbc").string();
    s.nav_path = esbc("ESBC00DNK_R_20201770000_01D_MN.rnx");
    s.atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx"), test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
    // The caster stream builder (ppp_stream_make's): station 1006/1033 once, GPS
    // MSM7 0.5 s after each epoch, no ephemerides (the nodes take the RINEX file).
    CasterStreamOptions options;
    options.systems = {GnssSystem::GPS};
    options.station_repeat_s = 0.0;
    CasterStreamBuilder builder(options);
    test::WindowObservationSource rinex(
        std::make_unique<RinexObservationSource>(esbc("ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz")), s.until);
    EXPECT_TRUE(rinex.header().approx_position_ecef_m.has_value());
    builder.setStation(rinex.header());
    ObsEpoch epoch;
    while (rinex.next(epoch) == ObservationRead::Epoch) builder.addEpoch(epoch);
    const auto precise = PreciseEphemeris::load({esbc("GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz")},
                                                {esbc("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz")});
    SsrFromPreciseOptions ssr_options;
    ssr_options.systems = {GnssSystem::GPS};
    const SsrFromPreciseResult ssr = ssrFromPrecise({readRinexNav(s.nav_path)}, precise, nullptr, nullptr,
                                                    s.start - 60.0, s.until + 60.0, ssr_options);
    std::vector<std::uint8_t> ssr_bytes;  // SSR 5 s, centre of mass, arriving 2 s after their epoch
    for (const auto& m : ssr.messages) {
      const auto f = encodeSsrFrame(m);
      ssr_bytes.insert(ssr_bytes.end(), f.begin(), f.end());
    }
    builder.addSsrStream(ssr_bytes, s.start);
    EXPECT_EQ(builder.counters().totalProblems(), 0u);
    s.obs = builder.observationFrames();
    s.ssr = builder.ssrFrames();
    s.obs_path = s.dir + "/ESBC_msm7.rtcm3";
    s.ssr_path = s.dir + "/SSRC00TST_esbc.rtcm3";
    writeFile(s.obs_path, concat(s.obs));
    writeFile(s.ssr_path, concat(s.ssr));
    return s;
  }();
  return streams;
}

/// The streams cut into chunks of random sizes (1..max_chunk bytes), each
/// arriving with its last byte, merged in arrival order.
std::vector<StreamChunk> chunked(const std::vector<std::pair<std::string, const std::vector<TimedFrame>*>>& streams,
                                 std::uint32_t seed, std::size_t max_chunk = 700) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> size(1, max_chunk);
  struct Item {
    double arrival_s;
    std::size_t order;
    StreamChunk chunk;
  };
  std::vector<Item> items;
  for (const auto& [name, frames] : streams) {
    std::vector<std::uint8_t> bytes;
    std::vector<double> arrival;  // per byte
    for (const auto& f : *frames) {
      bytes.insert(bytes.end(), f.bytes.begin(), f.bytes.end());
      arrival.insert(arrival.end(), f.bytes.size(), f.arrival_s);
    }
    for (std::size_t at = 0; at < bytes.size();) {
      const std::size_t n = std::min(size(rng), bytes.size() - at);
      StreamChunk c;
      c.stream = name;
      c.bytes.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.begin() + static_cast<std::ptrdiff_t>(at + n));
      c.arrival_time_s = arrival[at + n - 1];
      items.push_back({*c.arrival_time_s, items.size(), std::move(c)});
      at += n;
    }
  }
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.arrival_s < b.arrival_s; });
  std::vector<StreamChunk> out;
  for (auto& i : items) out.push_back(std::move(i.chunk));
  return out;
}

struct EpochResult {
  std::optional<Eigen::Vector3d> position_ecef_m;
  std::optional<Eigen::Matrix3d> covariance_ecef_m2;
  LiveProductMode mode = LiveProductMode::PreciseSsr;
};
using Solutions = std::map<GnssTime, EpochResult>;

Solutions batchRun(const PppInputFiles& files, const PppConfig& config, const std::string& estimator_name) {
  PppPipeline pipeline(files, config);
  std::string why;
  auto estimator = makeEstimator(estimator_name, pipeline.config(), &why);  // the products' systems and AR
  EXPECT_TRUE(estimator) << why;
  Solutions out;
  pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    if (rec.refused) return;
    out[rec.solution.time] = {rec.status == EpochStatus::Ok ? rec.solution.position_ecef_m : std::nullopt,
                              rec.solution.covariance_ecef_m2, LiveProductMode::PreciseSsr};
  });
  return out;
}

/// Feeds the chunks, processes the ready epochs as a node would.
struct LiveRun {
  Solutions solutions;
  std::vector<LiveStreamStatus> status;
  std::uint64_t precise = 0, broadcast = 0;
  std::size_t orbit_corrections_held = 0;
};

LiveRun liveRun(LiveInputOptions options, const std::vector<StreamChunk>& chunks, const PppConfig& config,
                const std::vector<std::string>& atx, const std::string& estimator_name) {
  LiveGnssInput live(std::move(options));
  // As the node: the products through the assembly (streamed orbits and clocks), the
  // estimator and the processor from its configuration, the SSR phase biases through its gate.
  ProductAssemblyInputs products_in;
  products_in.atx = atx;
  ProductAssembly products = ProductAssembly::assemble(products_in, config);
  const PppConfig& run_config = products.config();
  std::string why;
  auto estimator = makeEstimator(estimator_name, run_config, &why);
  EXPECT_TRUE(estimator) << why;
  std::unique_ptr<PppEpochProcessor> processor;
  bool approximate_set = false;
  LiveRun out;
  auto process = [&](std::vector<LiveReadyEpoch> ready) {
    if (ready.empty()) return;
    if (!processor) {
      processor = std::make_unique<PppEpochProcessor>(live.header(), run_config, live.ephemeris(), products.antennas(),
                                                      live.biases(), nullptr);
      live.takeHeaderChanged();
    } else if (live.takeHeaderChanged()) {
      processor->setObservationTypes(live.header());
    }
    if (live.hasPhaseBiases() && products.acceptStreamedPhaseBiases(live.biases(), PhaseInformation::SsrPhaseBiases))
      processor->setPhaseBiases(products.phaseBiases());
    if (!approximate_set && live.header().approx_position_ecef_m && live.header().approx_position_ecef_m->norm() > 1e6) {
      estimator->setApproximatePosition(*live.header().approx_position_ecef_m);
      approximate_set = true;
    }
    for (const auto& r : ready) {
      const PppEpochRecord rec = processor->process(r.epoch, *estimator);
      if (rec.refused) continue;
      out.solutions[rec.solution.time] = {rec.status == EpochStatus::Ok ? rec.solution.position_ecef_m : std::nullopt,
                                          rec.solution.covariance_ecef_m2, r.mode};
    }
  };
  for (const auto& c : chunks) {
    live.feed(c);
    process(live.takeReadyEpochs(c.arrival_time_s));
  }
  process(live.finish());
  out.status = live.streams();
  out.precise = live.releasedEpochs(LiveProductMode::PreciseSsr);
  out.broadcast = live.releasedEpochs(LiveProductMode::BroadcastOnly);
  out.orbit_corrections_held = live.corrections().orbitCount();
  return out;
}

/// Epochs solved in `a` and their largest 3D difference to `b` (an epoch solved
/// in one and not in the other counts as a mismatch).
struct Comparison {
  std::size_t compared = 0, mismatched = 0;
  double max_m = 0.0;
};
Comparison compare(const Solutions& a, const Solutions& b, std::optional<GnssTime> before = std::nullopt) {
  Comparison c;
  for (const auto& [t, x] : a) {
    if (before && !(t < *before)) continue;
    const auto it = b.find(t);
    if (it == b.end() || x.position_ecef_m.has_value() != it->second.position_ecef_m.has_value()) {
      if (std::getenv("PPP_LIVE_DEBUG")) std::printf("mismatch at %s\n", t.toString().c_str());
      ++c.mismatched;
      continue;
    }
    if (!x.position_ecef_m) continue;
    ++c.compared;
    c.max_m = std::max(c.max_m, (*x.position_ecef_m - *it->second.position_ecef_m).norm());
  }
  return c;
}

PppInputFiles esbcBatchFiles(const EsbcStreams& s) {
  PppInputFiles files;
  files.obs = s.obs_path;
  files.obs_format = ObservationFormat::Rtcm3;
  files.rtcm_reference_time = s.start;
  files.nav = {s.nav_path};
  files.ssr = s.ssr_path;
  files.atx = s.atx;
  return files;
}

LiveInputOptions esbcLiveOptions(const EsbcStreams& s) {
  LiveInputOptions o;
  o.reference_time = s.start;
  o.navigation_files = {s.nav_path};
  return o;
}

PppConfig realDataConfig() { return loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp_real_data.yaml"); }

TEST(LiveGnssInput, EsbcMsm7AndSsrChunksEqualTheBatchRun) {
  PPP_REQUIRE_SHARED_DATA();
  const EsbcStreams& s = esbcStreams();
  ASSERT_GT(s.obs.size(), 80u);
  ASSERT_GT(s.ssr.size(), 500u);
  const PppConfig config = realDataConfig();
  const auto chunks = chunked({{"/gnss/rtcm", &s.obs}, {"SSRC00TST_esbc", &s.ssr}}, 14);
  for (const std::string estimator : {"ekf", "smoother"}) {
    const Solutions batch = batchRun(esbcBatchFiles(s), config, estimator);
    const LiveRun live = liveRun(esbcLiveOptions(s), chunks, config, s.atx, estimator);
    const Comparison c = compare(batch, live.solutions);
    std::printf("ESBC %s: %zu epochs compared, %zu mismatched, max 3D difference live - batch %.6f mm; "
                "%llu precise SSR, %llu broadcast-only epochs\n",
                estimator.c_str(), c.compared, c.mismatched, c.max_m * 1e3,
                static_cast<unsigned long long>(live.precise), static_cast<unsigned long long>(live.broadcast));
    EXPECT_EQ(batch.size(), live.solutions.size()) << estimator;
    EXPECT_GT(c.compared, 80u) << estimator;
    EXPECT_EQ(c.mismatched, 0u) << estimator;
    EXPECT_LE(c.max_m, 1e-3) << estimator;
    EXPECT_EQ(live.broadcast, 0u) << estimator;
    // Bounded memory: of the 45 min of 5-s orbit corrections (~6000) only the
    // last minutes per satellite are held.
    EXPECT_LT(live.orbit_corrections_held, 32u * 20u) << estimator;
    std::printf("orbit corrections held at the end: %zu\n", live.orbit_corrections_held);
    for (const auto& st : live.status) EXPECT_EQ(st.problems.totalProblems(), 0u) << st.stream;
  }
}

TEST(LiveGnssInput, RecordingBroadcastOnlyEqualsPppSolveNavFromTheStream) {
  PPP_REQUIRE_SHARED_DATA();
  // STR2 (week rollover): MSM4, ephemerides 1019/1045/1046 and station 1006 in the stream.
  const std::string rec = test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3");
  const PppConfig config = realDataConfig();
  const std::vector<std::string> atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx")};
  PppInputFiles files;
  files.obs = rec;
  files.obs_format = ObservationFormat::Rtcm3;
  files.nav = {rec};
  files.atx = atx;
  const Solutions batch = batchRun(files, config, "ekf");

  std::ifstream in(rec, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<TimedFrame> frames{{0.0, bytes, GnssTime()}};
  LiveInputOptions options;
  options.expect_corrections = false;  // no correction stream: broadcast only
  const LiveRun live = liveRun(options, chunked({{"/rtcm", &frames}}, 7, 1500), config, atx, "ekf");
  const Comparison c = compare(batch, live.solutions);
  std::printf("STR2 broadcast-only: %zu epochs compared, %zu mismatched, max 3D difference %.6f mm\n", c.compared,
              c.mismatched, c.max_m * 1e3);
  EXPECT_GT(c.compared, 1000u);
  EXPECT_EQ(c.mismatched, 0u);
  EXPECT_LE(c.max_m, 1e-3);
  EXPECT_EQ(live.precise, 0u);
  EXPECT_EQ(live.broadcast, batch.size());
  ASSERT_EQ(live.status.size(), 1u);
  EXPECT_GT(live.status[0].ephemerides, 10u);
  EXPECT_GT(live.status[0].problems.count(StreamProblemKind::Garbage), 0u);  // 208 bytes before the first frame
}

TEST(LiveGnssInput, SsrOutageFallsBackToBroadcastWithWiderCovarianceAndReturns) {
  PPP_REQUIRE_SHARED_DATA();
  const EsbcStreams& s = esbcStreams();
  PppConfig config = realDataConfig();
  config.model.ephemeris_sigmas = true;
  // The correction stream stops for 12 minutes (00:15-00:27).
  const GnssTime cut_from = s.start + 15 * 60.0, cut_to = s.start + 27 * 60.0;
  std::vector<TimedFrame> ssr;
  for (const auto& f : s.ssr)
    if (f.data_time < cut_from || !(f.data_time < cut_to)) ssr.push_back(f);
  const LiveRun live = liveRun(esbcLiveOptions(s), chunked({{"/gnss/rtcm", &s.obs}, {"SSRC00TST_esbc", &ssr}}, 3), config,
                               s.atx, "ekf");
  const LiveRun clean = liveRun(esbcLiveOptions(s), chunked({{"/gnss/rtcm", &s.obs}, {"SSRC00TST_esbc", &s.ssr}}, 3),
                                config, s.atx, "ekf");
  // Corrections stay valid 90 s after the last one (SsrAgeLimits), then broadcast only until they return.
  std::size_t fallback = 0, fallback_solved = 0, after = 0;
  double sigma_before_m = 0.0, sigma_fallback_m = 0.0;
  for (const auto& [t, r] : live.solutions) {
    const bool in_outage = cut_from + 95.0 < t && t < cut_to;
    if (in_outage) {
      EXPECT_EQ(r.mode, LiveProductMode::BroadcastOnly) << t.toString();
      ++fallback;
      if (r.position_ecef_m && r.covariance_ecef_m2) {
        ++fallback_solved;
        sigma_fallback_m = std::max(sigma_fallback_m, std::sqrt(r.covariance_ecef_m2->trace()));
      }
    } else if (t < cut_from || cut_to + 5.0 < t) {
      EXPECT_EQ(r.mode, LiveProductMode::PreciseSsr) << t.toString();
      if (!(t < cut_to)) ++after;
      if (t < cut_from && cut_from - t < 120.0 && r.covariance_ecef_m2)
        sigma_before_m = std::max(sigma_before_m, std::sqrt(r.covariance_ecef_m2->trace()));
    }
  }
  std::printf("SSR outage: %zu broadcast-only epochs (%zu solved), 3D sigma before %.3f m, in the outage up to %.3f m, "
              "%zu precise epochs after\n",
              fallback, fallback_solved, sigma_before_m, sigma_fallback_m, after);
  EXPECT_GE(fallback, 20u);
  EXPECT_GE(fallback_solved, fallback * 9 / 10);
  EXPECT_GT(sigma_fallback_m, 2.0 * sigma_before_m);
  EXPECT_GE(after, 30u);
  EXPECT_EQ(live.solutions.size(), clean.solutions.size());  // every epoch went out
  const Comparison before = compare(clean.solutions, live.solutions, cut_from);
  EXPECT_EQ(before.mismatched, 0u);
  EXPECT_LE(before.max_m, 1e-9);
}

/// The mode each epoch is released with (no estimator: the decision only).
std::map<GnssTime, LiveProductMode> liveModes(LiveInputOptions options, const std::vector<StreamChunk>& chunks) {
  LiveGnssInput live(std::move(options));
  std::map<GnssTime, LiveProductMode> modes;
  const auto take = [&](const std::vector<LiveReadyEpoch>& ready) {
    for (const auto& r : ready) modes[r.epoch.time] = r.mode;
  };
  for (const auto& c : chunks) {
    live.feed(c);
    take(live.takeReadyEpochs(c.arrival_time_s));
  }
  take(live.finish());
  return modes;
}

// One broadcast fallback rule (models/broadcast_fallback.h) with one set of keys
// (`ssr:`): the offline products (ppp_solve --nav --ssr: SsrBroadcastFallback)
// and the live input, given the same keys and the same SSR stream with a
// 12-minute outage, choose SSR or broadcast alike at every epoch away from the
// outage's edges (there the offline count covers the stream's satellites, the
// live one the epoch's, and the live input holds the epoch up to
// correction_wait_s). Three settings: the defaults (broadcast in the outage only),
// the fallback off (SSR everywhere), 100 satellites needed (broadcast everywhere).
TEST(LiveGnssInput, OfflineAndLiveChooseSsrOrBroadcastAlikeWithTheSameSsrKeys) {
  PPP_REQUIRE_SHARED_DATA();
  const EsbcStreams& s = esbcStreams();
  const GnssTime cut_from = s.start + 15 * 60.0, cut_to = s.start + 27 * 60.0;
  std::vector<TimedFrame> ssr;
  for (const auto& f : s.ssr)
    if (f.data_time < cut_from || !(f.data_time < cut_to)) ssr.push_back(f);
  const std::string ssr_path = s.dir + "/SSRC00TST_esbc_outage.rtcm3";
  writeFile(ssr_path, concat(ssr));
  const auto chunks = chunked({{"/gnss/rtcm", &s.obs}, {"SSRC00TST_esbc", &ssr}}, 5);
  struct Setting {
    const char* ssr_keys;
    std::size_t min_broadcast, max_broadcast;  // epochs in fallback (of ~90)
  };
  for (const Setting& setting : {Setting{"{}", 20, 30}, Setting{"{broadcast_fallback: false}", 0, 0},
                                 Setting{"{min_ssr_satellites: 100}", 80, 100}}) {
    const PppConfig config = bindPppConfig(YAML::Load(std::string("ssr: ") + setting.ssr_keys), "test");
    const BroadcastProducts offline =
        loadBroadcastProducts({s.nav_path}, ssr_path, std::nullopt, config.ssr, config.ssr.fallback, s.start);
    const auto* fallback = dynamic_cast<const SsrBroadcastFallback*>(offline.ephemeris.get());
    ASSERT_NE(fallback, nullptr);
    LiveInputOptions options = esbcLiveOptions(s);
    options.fallback = config.ssr.fallback;  // as the node (loadNodeConfig)
    const auto live = liveModes(options, chunks);
    std::size_t compared = 0, broadcast = 0, differ = 0;
    for (const auto& [t, mode] : live) {
      const bool edge = (!(t < cut_from) && t < cut_from + 120.0) || (!(t < cut_to) && t < cut_to + 15.0);
      if (edge) continue;
      ++compared;
      const bool live_ssr = mode == LiveProductMode::PreciseSsr;
      if (!live_ssr) ++broadcast;
      if (live_ssr != fallback->preciseAt(t)) {
        ++differ;
        ADD_FAILURE() << setting.ssr_keys << ": at " << t.toString() << " live "
                      << liveProductModeName(mode) << ", offline " << (live_ssr ? "broadcast" : "SSR");
      }
    }
    std::printf("ssr: %s: %zu epochs compared, %zu in broadcast fallback, %zu differ\n", setting.ssr_keys, compared,
                broadcast, differ);
    EXPECT_GT(compared, 70u);
    EXPECT_GE(broadcast, setting.min_broadcast) << setting.ssr_keys;
    EXPECT_LE(broadcast, setting.max_broadcast) << setting.ssr_keys;
  }
}

TEST(LiveGnssInput, GarbageCrcErrorsAndTimeBackwardsAreCountedPerStream) {
  PPP_REQUIRE_SHARED_DATA();
  const EsbcStreams& s = esbcStreams();
  const PppConfig config = realDataConfig();
  // Observation stream: 300 garbage bytes after epoch 20, the frames of epoch
  // 40 sent again after epoch 41 (time backwards), one byte of epoch 60 flipped (CRC).
  std::vector<TimedFrame> obs;
  std::mt19937 rng(5);
  std::vector<GnssTime> times;
  for (const auto& f : s.obs)
    if (times.empty() || times.back() != f.data_time) times.push_back(f.data_time);
  ASSERT_GT(times.size(), 70u);
  for (std::size_t i = 0; i < s.obs.size(); ++i) {
    TimedFrame f = s.obs[i];
    if (f.data_time == times[60]) f.bytes[f.bytes.size() / 2] ^= 0x5A;
    obs.push_back(f);
    const bool last_of_epoch = i + 1 == s.obs.size() || s.obs[i + 1].data_time != f.data_time;
    if (last_of_epoch && f.data_time == times[20]) {
      TimedFrame g{f.arrival_s, std::vector<std::uint8_t>(300), f.data_time};
      for (auto& b : g.bytes) b = static_cast<std::uint8_t>(rng() % 0xD3);  // no preamble: one garbage run
      obs.push_back(g);
    }
    if (last_of_epoch && f.data_time == times[41])
      for (const auto& h : s.obs)
        if (h.data_time == times[40]) obs.push_back({f.arrival_s, h.bytes, h.data_time});
  }
  const LiveRun clean = liveRun(esbcLiveOptions(s), chunked({{"/gnss/rtcm", &s.obs}, {"SSRC00TST_esbc", &s.ssr}}, 9),
                                config, s.atx, "ekf");
  const LiveRun bad =
      liveRun(esbcLiveOptions(s), chunked({{"/gnss/rtcm", &obs}, {"SSRC00TST_esbc", &s.ssr}}, 9), config, s.atx, "ekf");
  ASSERT_EQ(bad.status.size(), 2u);
  const LiveStreamStatus& o = bad.status[0].stream == "/gnss/rtcm" ? bad.status[0] : bad.status[1];
  const LiveStreamStatus& c = bad.status[0].stream == "/gnss/rtcm" ? bad.status[1] : bad.status[0];
  // The garbage run, and the bytes of the corrupted frame skipped while resynchronising.
  EXPECT_GE(o.problems.count(StreamProblemKind::Garbage), 1u);
  EXPECT_GE(o.problems.count(StreamProblemKind::ChecksumError), 1u);
  EXPECT_EQ(o.time_backwards, 1u);
  EXPECT_EQ(c.problems.totalProblems(), 0u);
  EXPECT_GT(c.ssr_messages, 500u);
  // Up to the corrupted epoch the estimates are those of the clean run.
  const Comparison before = compare(clean.solutions, bad.solutions, times[60]);
  std::printf("bad bytes: %llu garbage run(s), %llu CRC error(s), %llu epoch(s) back in time; %zu epochs before the "
              "CRC error equal to %.3g mm\n",
              static_cast<unsigned long long>(o.problems.count(StreamProblemKind::Garbage)),
              static_cast<unsigned long long>(o.problems.count(StreamProblemKind::ChecksumError)),
              static_cast<unsigned long long>(o.time_backwards), before.compared, before.max_m * 1e3);
  EXPECT_EQ(before.mismatched, 0u);
  EXPECT_LE(before.max_m, 1e-9);
  EXPECT_GE(before.compared, 55u);
  // After it the run goes on.
  std::size_t solved_after = 0;
  for (const auto& [t, r] : bad.solutions)
    if (times[60] < t && r.position_ecef_m) ++solved_after;
  EXPECT_GE(solved_after, times.size() - 62);
}

}  // namespace
}  // namespace ppp

namespace ppp {
namespace {

TEST(LiveGnssInput, UbxRecordingGivesTheEpochsOfPppSolve) {
  PPP_REQUIRE_SHARED_DATA();
  // u-blox F9 walk: RXM-RAWX epochs and RXM-SFRBX ephemerides in one stream, cut into
  // chunks, through LiveGnssInput as a node runs it, against ppp_solve --ubx X --nav X
  // with the live rostest's configuration (config/live.yaml + test/rostest/live_ubx.yaml:
  // GPS + Galileo, fixed-lag smoother). No approximate position in a UBX recording: both
  // runs start on the start model (PppEstimator step 1) once the ephemerides allow;
  // EKF and smoother filtered must agree epoch by epoch (solved or not) to 1 mm.
  const std::string rec = test::dataPath("streams/ubx/gnss_1730.ubx");
  const std::string repo = PPP_REPO_DIR;
  const PppConfig config =
      loadPppConfig(std::vector<std::string>{repo + "/config/live.yaml", repo + "/test/rostest/live_ubx.yaml"});
  const std::vector<std::string> atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx")};
  PppInputFiles files;
  files.obs = rec;
  files.obs_format = ObservationFormat::Ubx;
  files.nav = {rec};
  files.atx = atx;

  std::ifstream in(rec, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<TimedFrame> frames{{0.0, bytes, GnssTime()}};
  LiveInputOptions options;
  options.expect_corrections = false;
  const auto chunks = chunked({{"/ublox", &frames}}, 11, 900);
  for (auto& c : const_cast<std::vector<StreamChunk>&>(chunks)) c.format = StreamFormat::Ubx;
  for (const std::string estimator : {"ekf", "smoother"}) {
    const Solutions batch = batchRun(files, config, estimator);
    const LiveRun live = liveRun(options, chunks, config, atx, estimator);
    const Comparison c = compare(batch, live.solutions);
    std::size_t solved = 0;
    for (const auto& [t, r] : batch) solved += r.position_ecef_m.has_value();
    std::printf("UBX broadcast-only, %s: %zu epochs (batch %zu, %zu solved), %zu compared, %zu mismatched, max 3D "
                "difference %.6f mm\n",
                estimator.c_str(), live.solutions.size(), batch.size(), solved, c.compared, c.mismatched, c.max_m * 1e3);
    EXPECT_EQ(live.solutions.size(), batch.size()) << estimator;
    EXPECT_EQ(batch.size(), 536u) << estimator;  // RXM-RAWX epochs (data README)
    EXPECT_GE(solved, 300u) << estimator;         // 338 when written (UbxWalk.PppWithoutApproximatePositionStartsOnItsOwn)
    EXPECT_EQ(c.compared, solved) << estimator;
    EXPECT_EQ(c.mismatched, 0u) << estimator;
    EXPECT_LE(c.max_m, 1e-3) << estimator;
    ASSERT_EQ(live.status.size(), 1u);
    EXPECT_EQ(live.status[0].format, StreamFormat::Ubx);
    EXPECT_GT(live.status[0].ephemerides, 5u);
  }
}

}  // namespace
}  // namespace ppp

#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"

namespace ppp {
namespace {

TEST(LiveGnssInput, ARecordServesOnlyInstantsAfterItsReception) {
  PPP_REQUIRE_SHARED_DATA();
  const NavData nav = readRinexNav(esbc("ESBC00DNK_R_20201770000_01D_MN.rnx"));
  ASSERT_FALSE(nav.gps.empty());
  const GpsLnavEphemeris& e = nav.gps.front();
  const GnssTime received = e.orbit.toe + 10.0;
  BroadcastEphemerisStore store;
  ASSERT_FALSE(store.add(e, received).has_value());
  EXPECT_FALSE(store.satelliteOrbit(e.satellite, e.orbit.toe + 5.0).ok());   // not yet received
  EXPECT_FALSE(store.satelliteOrbit(e.satellite, received).ok());            // strictly after
  EXPECT_TRUE(store.satelliteOrbit(e.satellite, e.orbit.toe + 15.0).ok());
  BroadcastEphemerisStore preloaded;  // a RINEX record (no reception time) serves every instant
  ASSERT_FALSE(preloaded.add(e).has_value());
  EXPECT_TRUE(preloaded.satelliteOrbit(e.satellite, e.orbit.toe - 600.0).ok());
}

TEST(LiveGnssInput, ObservationStreamStallGoesWarnThenError) {
  PPP_REQUIRE_SHARED_DATA();
  std::ifstream in(test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3"), std::ios::binary);
  std::vector<std::uint8_t> bytes(200000);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  LiveInputOptions options;
  options.expect_corrections = false;
  LiveGnssInput live(options);
  live.feed(StreamChunk{"/dev/ttyACM0", StreamFormat::Rtcm3, bytes, 1000.0});
  const auto ready = live.takeReadyEpochs(1000.5);
  EXPECT_GT(ready.size(), 100u);
  for (const auto& r : ready) EXPECT_EQ(r.mode, LiveProductMode::BroadcastOnly);
  EXPECT_EQ(live.streams().at(0).stall, StreamStall::Ok);
  live.takeReadyEpochs(1003.0);
  EXPECT_EQ(live.streams().at(0).stall, StreamStall::Warn);
  live.takeReadyEpochs(1011.0);
  EXPECT_EQ(live.streams().at(0).stall, StreamStall::Error);
  EXPECT_EQ(live.mode(), LiveProductMode::BroadcastOnly);
  EXPECT_GT(live.navigationRecords(), 10u);
  EXPECT_TRUE(live.header().approx_position_ecef_m.has_value());  // 1006
}

}  // namespace
}  // namespace ppp

namespace ppp {
namespace {

TEST(LiveGnssInput, ReceiverRestartWithATimeJumpBackIsCountedAndGoesOn) {
  PPP_REQUIRE_SHARED_DATA();
  const EsbcStreams& s = esbcStreams();
  std::vector<TimedFrame> twice = s.obs;  // the recording played twice, as a looping bag or a restarted receiver
  for (const auto& f : s.obs) twice.push_back({f.arrival_s + 3600.0, f.bytes, f.data_time});
  LiveInputOptions options = esbcLiveOptions(s);
  options.expect_corrections = false;
  LiveGnssInput live(options);
  std::size_t released = 0;
  for (const auto& c : chunked({{"/gnss/rtcm", &twice}}, 21)) {
    live.feed(c);
    released += live.takeReadyEpochs(c.arrival_time_s).size();
  }
  released += live.finish().size();
  std::size_t epochs = 0;
  for (std::size_t i = 0; i < s.obs.size(); ++i)
    if (i == 0 || s.obs[i].data_time != s.obs[i - 1].data_time) ++epochs;
  epochs -= 1;  // the station frames (1006, 1033) sent ahead of the first epoch
  ASSERT_EQ(live.streams().size(), 1u);
  EXPECT_EQ(live.streams()[0].restarts, 1u);
  EXPECT_EQ(live.streams()[0].time_backwards, 0u);
  EXPECT_EQ(released, 2 * epochs);
}

}  // namespace
}  // namespace ppp

namespace ppp {
namespace {

// The end-to-end latency the nodes report (ppp_node.h, scripts/bench_live_realtime.sh)
// is measured from LiveReadyEpoch::arrival_s: the arrival of the chunk that completed
// the epoch. On a real recording fed one frame per chunk (arrival = the frame's index),
// broadcast only: each epoch is released by the chunk holding its last MSM frame (the
// multiple-message bit 0 of RTCM 10403.3 DF393 closes the epoch; no wait for the next
// epoch's first frame) and carries that chunk's arrival.
TEST(LiveGnssInput, AnEpochGoesOutWithTheArrivalOfItsLastMsmFrame) {
  PPP_REQUIRE_SHARED_DATA();
  std::ifstream in(test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3"), std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000000u);
  std::vector<Rtcm3Frame> frames;
  Rtcm3Framer framer;
  framer.feed(bytes.data(), bytes.size(), [&](const Rtcm3Frame& f) { frames.push_back(f); });
  // Index of the last frame of each epoch (GPS/Galileo/QZSS/BeiDou MSM time of week, modulo
  // 1 s-rounding-safe milliseconds; GLONASS MSM carries a time of day and is not timed here).
  std::map<long long, std::size_t> last_frame_of_epoch;
  for (std::size_t k = 0; k < frames.size(); ++k)
    if (const auto tow_s = rtcm3EpochTimeOfWeek_s(frames[k].payload))
      last_frame_of_epoch[std::llround(*tow_s * 1000.0)] = k;
  LiveInputOptions options;
  options.expect_corrections = false;
  options.station_wait_s = 0.0;
  options.reference_time = GnssTime::fromCalendar({2018, 7, 14, 0, 0, 0.0}, TimeSystem::GPS);
  LiveGnssInput live(options);
  // The stream's first epochs wait for their time line (io/epoch_time_screen.h: the
  // first confirm_epochs epochs that follow each other set it): they go out together
  // with the last of them, each with the arrival of its own last frame.
  const std::size_t startup = streamEpochTimeOptions().confirm_epochs;
  std::size_t released = 0, at_last_frame = 0, startup_released = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    live.feed(StreamChunk{"/gnss/receiver", StreamFormat::Rtcm3, encodeRtcm3Frame(frames[k].payload),
                          static_cast<double>(k)});
    for (const LiveReadyEpoch& r : live.takeReadyEpochs(static_cast<double>(k))) {
      ++released;
      ASSERT_TRUE(r.arrival_s.has_value());
      const double tow_s = std::fmod(r.epoch.time.toGpsSecondsDouble(), 604800.0);
      const auto it = last_frame_of_epoch.find(std::llround(tow_s * 1000.0));
      ASSERT_NE(it, last_frame_of_epoch.end()) << r.epoch.time.toString();
      EXPECT_EQ(*r.arrival_s, static_cast<double>(it->second));
      if (released < startup) {
        ++startup_released;
        continue;
      }
      EXPECT_EQ(*r.arrival_s, static_cast<double>(k));
      if (it->second == k) ++at_last_frame;
    }
  }
  // The recording's epochs (1,134 MSM4 frames of each of GLONASS, Galileo, QZSS and BeiDou; GPS
  // misses one), all released on the way, none held to the end.
  EXPECT_EQ(released, 1134u);
  EXPECT_EQ(startup_released, startup - 1);
  EXPECT_EQ(at_last_frame, released - startup_released);
  EXPECT_TRUE(live.finish().empty());
}

// A Galileo HAS internet-distribution stream as the live correction stream
// (test/fixtures/ssr/README.md, the first 20 s of the OBE4 recording): its
// code biases, re-sent with the epoch of their issue 12 h before, are in force
// from their arrival as in ppp_solve, counted per stream; its ephemerides are
// read from the same stream.
TEST(LiveGnssInput, HasIddStreamCodeBiasesReSentWithAnOldEpochAreInForceFromTheirArrival) {
  std::ifstream in(test::fixturePath("ssr/has_idd_20230817_0159.rtcm3"), std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 7147u);
  LiveInputOptions options;
  options.reference_time = test::gpst(2023, 8, 17);
  LiveGnssInput live(options);
  // In chunks of 500 bytes, as a caster's TCP segments arrive.
  for (std::size_t i = 0; i < bytes.size(); i += 500) {
    const std::vector<std::uint8_t> chunk(bytes.begin() + static_cast<std::ptrdiff_t>(i),
                                          bytes.begin() + static_cast<std::ptrdiff_t>(std::min(bytes.size(), i + 500)));
    live.feed(StreamChunk{"HAS_IDD", StreamFormat::Rtcm3, chunk, 1000.0 + static_cast<double>(i) / 1000.0});
  }
  live.takeReadyEpochs(1010.0);
  ASSERT_EQ(live.streams().size(), 1u);
  const LiveStreamStatus& st = live.streams().front();
  EXPECT_EQ(st.ssr_messages, 8u);
  EXPECT_EQ(st.ssr_code_biases_resent, live.corrections().staleCodeBiasMessages());
  EXPECT_EQ(st.ssr_code_biases_resent, 3u);  // as in ppp_solve (test_ssr_conventions_real_data)
  EXPECT_EQ(st.problems.totalProblems(), 0u);
  EXPECT_EQ(live.navigationRecords(), 51u);
  const auto g02 = live.corrections().codeBias({GnssSystem::GPS, 2}, test::gpst(2023, 8, 17, 1, 59, 30));
  ASSERT_TRUE(g02) << g02.reason;
  EXPECT_EQ(g02.entry->t0, test::gpst(2023, 8, 16, 14, 0, 21));
  EXPECT_EQ(g02.entry->in_force_from, test::gpst(2023, 8, 17, 1, 59, 12));
}

}  // namespace
}  // namespace ppp
