// Integrity regression suite: epoch time and corrections. Each case puts the
// clean real recording of ../shared/data/streams beside a faulty copy made here
// at run time in a temporary directory (bytes edited, the UBX checksum or RTCM
// CRC-24Q recomputed; nothing is committed), and asserts what must hold:
//  - one u-blox RXM-RAWX with its week one too high (gnss_1730.ubx, the 201st
//    RXM-RAWX): ppp_solve --ubx and the live input (LiveGnssInput, as the nodes
//    run it) drop that epoch only, counted with its reason and byte offset, and
//    give the same epochs; the fixes of the clean run are recovered (all but the
//    dropped epoch's); no restart is counted; the same when it is the first epoch;
//  - one RTCM 3 MSM frame (STR24, the 300th 1074) with its time of week two days
//    ahead: the same, offline and live alike;
//  - an SSR stream of another day (SSRA03IGS0 of 2026-07-07 against the walk of
//    2025-08-28): both paths fall back to broadcast orbits and clocks, the SSR
//    code biases do not apply, the epochs are solved as without the stream, and
//    the run notes say so with the corrections' age;
//  - a --ref-date one week off for STR24: refused, naming the date and the
//    stream's ephemerides that contradict it (live: a warning in the stream
//    status and the log); the right date is accepted;
//  - broadcast URA in metres: the nominal value of IS-GPS-200 20.3.3.3.1.1 (4.0 m
//    for index 2, as RINEX and convbin write), on STR24's 1019/1044 records; the
//    QZSS L2P data flag 1.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/app/live_gnss_input.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/types/broadcast_accuracy.h"
#include "test_support.h"

namespace ppp {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string ubxWalk() { return test::dataPath("streams/ubx/gnss_1730.ubx"); }
std::string str24() { return test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3"); }
std::string staleSsr() { return test::dataPath("streams/ssr/SSRA03IGS0_2026188140760_3epoch.rtcm3"); }

/// The byte offset of the `n`-th (0-based) UBX frame of class/id in `b`.
std::size_t ubxFrameOffset(const Bytes& b, int message_class, int message_id, std::size_t n) {
  for (std::size_t i = 0; i + 8 <= b.size();) {
    if (b[i] == 0xB5 && b[i + 1] == 0x62) {
      const std::size_t len = b[i + 4] | (static_cast<std::size_t>(b[i + 5]) << 8);
      if (b[i + 2] == message_class && b[i + 3] == message_id && n-- == 0) return i;
      i += 8 + len;
    } else {
      ++i;
    }
  }
  ADD_FAILURE() << "UBX frame not found";
  return 0;
}

/// gnss_1730.ubx with the week of one RXM-RAWX one too high (checksum recomputed).
Bytes ubxWithBadWeek(std::size_t rawx_index, std::size_t& offset) {
  Bytes b = readBytes(ubxWalk());
  offset = ubxFrameOffset(b, 0x02, 0x15, rawx_index);
  const std::size_t len = b[offset + 4] | (static_cast<std::size_t>(b[offset + 5]) << 8);
  std::uint8_t* p = b.data() + offset + 6;  // payload; week: u2 at 8 (u-blox interface description, RXM-RAWX)
  const int week = p[8] | (p[9] << 8);
  p[8] = static_cast<std::uint8_t>((week + 1) & 0xFF);
  p[9] = static_cast<std::uint8_t>((week + 1) >> 8);
  const UbxChecksum ck = ubxChecksum(b.data() + offset + 2, len + 4);
  b[offset + 6 + len] = ck.a;
  b[offset + 7 + len] = ck.b;
  return b;
}

/// STR24 with the GPS epoch time (DF004, 30 bits after the message number and
/// station id) of the `n`-th 1074 frame moved `days` ahead (CRC-24Q recomputed).
Bytes rtcmWithTowAhead(std::size_t n, double days, std::size_t& offset) {
  Bytes b = readBytes(str24());
  for (std::size_t i = 0; i + 6 <= b.size();) {
    const std::size_t len = b[i] == 0xD3 ? ((b[i + 1] & 0x03u) << 8 | b[i + 2]) : 0;
    if (b[i] != 0xD3 || i + 6 + len > b.size() ||
        crc24q(b.data() + i, 3 + len) != (std::uint32_t(b[i + 3 + len]) << 16 | std::uint32_t(b[i + 4 + len]) << 8 |
                                          b[i + 5 + len])) {
      ++i;
      continue;
    }
    const int type = (b[i + 3] << 4) | (b[i + 4] >> 4);
    if (type == 1074 && n-- == 0) {
      std::uint64_t v = 0;
      for (int k = 0; k < 8; ++k) v = (v << 8) | b[i + 3 + k];
      const std::uint64_t mask = ((std::uint64_t(1) << 30) - 1) << (64 - 54);
      const std::uint64_t tow_ms = (v & mask) >> (64 - 54);
      const std::uint64_t moved = (tow_ms + static_cast<std::uint64_t>(days * 86400000.0)) % 604800000u;
      v = (v & ~mask) | (moved << (64 - 54));
      for (int k = 7; k >= 0; --k, v >>= 8) b[i + 3 + k] = static_cast<std::uint8_t>(v & 0xFF);
      const std::uint32_t crc = crc24q(b.data() + i, 3 + len);
      b[i + 3 + len] = static_cast<std::uint8_t>(crc >> 16);
      b[i + 4 + len] = static_cast<std::uint8_t>(crc >> 8);
      b[i + 5 + len] = static_cast<std::uint8_t>(crc);
      offset = i;
      return b;
    }
    i += 6 + len;
  }
  ADD_FAILURE() << "1074 frame not found";
  return b;
}

std::string writeTemp(const std::string& tag, const std::string& name, const Bytes& bytes) {
  const std::string path = (test::tempDir(tag) / name).string();
  test::writeFileBytes(path, bytes);
  return path;
}

PppConfig ubxConfig() {
  const std::string repo = PPP_REPO_DIR;
  return loadPppConfig(std::vector<std::string>{repo + "/config/live.yaml", repo + "/test/rostest/live_ubx.yaml"});
}

/// ppp_solve's run (EKF) on a recording with its own ephemerides (--nav = the recording).
PppSolveOutcome solve(const std::string& obs, ObservationFormat format, const PppConfig& config,
                      std::optional<std::string> ssr = std::nullopt) {
  PppSolveRequest r;
  r.files.obs = obs;
  r.files.obs_format = format;
  r.files.nav = {obs};
  r.files.ssr = ssr;
  r.files.atx = {test::dataPath("antex/igs14_2178_satellites.atx"), test::dataPath("antex/igs20_gps_satellites_trim.atx")};
  if (format == ObservationFormat::Ubx) r.files.atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx")};
  r.config = config;
  r.estimator = "ekf";
  r.out_dir = test::tempDir("integrity_time_out").string();
  return solvePpp(r);
}

/// The epoch times an offline reader serves.
std::vector<GnssTime> offlineTimes(ObservationSource& source) {
  std::vector<GnssTime> t;
  ObsEpoch e;
  while (source.next(e) == ObservationRead::Epoch) t.push_back(e.time);
  return t;
}

/// The live input as the nodes run it: the recording (and an SSR stream) fed in
/// chunks; each ready epoch processed (EKF) when `config` is given.
struct LiveOutcome {
  std::vector<GnssTime> times;
  std::vector<LiveStreamStatus> status;
  std::size_t solved = 0, broadcast_only = 0;
  bool ssr_biases_applied = false;  // some SSR code bias applied at a released epoch
  std::vector<std::string> time_events;  // LiveGnssInput::takeTimeEvents (the node logs them)
};

LiveOutcome runLive(const Bytes& obs, StreamFormat format, const PppConfig* config, const Bytes* ssr = nullptr,
                    bool expect_corrections = false, std::optional<GnssTime> reference_time = std::nullopt) {
  LiveInputOptions options;
  options.expect_corrections = expect_corrections;
  options.reference_time = reference_time;
  LiveGnssInput live(options);
  LiveOutcome out;
  std::unique_ptr<ProductAssembly> products;
  std::unique_ptr<PppEstimator> estimator;
  std::unique_ptr<PppEpochProcessor> processor;
  if (config) {
    ProductAssemblyInputs in;
    in.atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx")};
    products = std::make_unique<ProductAssembly>(ProductAssembly::assemble(in, *config));
    std::string why;
    estimator = makeEstimator("ekf", products->config(), &why);
    EXPECT_TRUE(estimator) << why;
  }
  auto process = [&](const std::vector<LiveReadyEpoch>& ready) {
    for (auto& e : live.takeTimeEvents()) out.time_events.push_back(std::move(e));
    for (const auto& r : ready) {
      out.times.push_back(r.epoch.time);
      out.broadcast_only += r.mode == LiveProductMode::BroadcastOnly;
      if (live.biases()) {
        for (const auto& sat : r.epoch.satellites) {
          const BiasAnswer a = live.biases()->codeBias(sat.satellite, *ObservationCode::parse("C1C"), r.epoch.time);
          out.ssr_biases_applied |= a.applies && a.value_m.has_value();
        }
      }
      if (!config) continue;
      if (!processor) {
        processor = std::make_unique<PppEpochProcessor>(live.header(), products->config(), live.ephemeris(),
                                                        products->antennas(), live.biases(), nullptr);
        live.takeHeaderChanged();
      } else if (live.takeHeaderChanged()) {
        processor->setObservationTypes(live.header());
      }
      const PppEpochRecord rec = processor->process(r.epoch, *estimator);
      out.solved += !rec.refused && rec.status == EpochStatus::Ok;
    }
  };
  constexpr std::size_t kChunk = 4096;
  auto feed = [&](const Bytes& bytes, const std::string& name, StreamFormat f, std::size_t at, std::size_t n) {
    StreamChunk c;
    c.stream = name;
    c.format = f;
    c.bytes.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.begin() + static_cast<std::ptrdiff_t>(at + n));
    live.feed(c);
  };
  if (ssr) feed(*ssr, "SSRA03IGS0", StreamFormat::Rtcm3, 0, ssr->size());  // a caster's stream, first
  for (std::size_t at = 0; at < obs.size(); at += kChunk) {
    feed(obs, "/receiver", format, at, std::min(kChunk, obs.size() - at));
    process(live.takeReadyEpochs());
  }
  process(live.finish());
  out.status = live.streams();
  return out;
}

const LiveStreamStatus& observationStatus(const LiveOutcome& o) {
  for (const auto& s : o.status)
    if (s.stream == "/receiver") return s;
  return o.status.front();
}

bool anyContains(const std::vector<std::string>& lines, const std::string& a, const std::string& b = "") {
  for (const auto& l : lines)
    if (l.find(a) != std::string::npos && l.find(b) != std::string::npos) return true;
  return false;
}

/// The faulty run lost the bad epoch only: one epoch fewer read, none refused,
/// every fix of the clean run but at most that epoch's.
void expectOnlyTheBadEpochLost(const std::string& what, const PppSolveOutcome& clean, const PppSolveOutcome& faulty) {
  std::printf("%s: clean %zu read %zu solved; faulty %zu read %zu solved %zu refused\n", what.c_str(),
              clean.run.epochs_read, clean.run.epochs_solved, faulty.run.epochs_read, faulty.run.epochs_solved,
              faulty.run.epochs_refused);
  EXPECT_EQ(faulty.run.epochs_read, clean.run.epochs_read - 1) << what;
  EXPECT_EQ(faulty.run.epochs_refused, 0u) << what;
  EXPECT_GE(faulty.run.epochs_solved + 1, clean.run.epochs_solved) << what;
}

/// The walk with one RXM-RAWX a week late, written to a temporary file, and
/// ppp_solve --ubx F --nav F on the clean and on the faulty recording.
struct UbxWeekCase {
  std::size_t offset = 0;  // of the edited frame
  Bytes bytes;
  std::string path;
  PppSolveOutcome clean, faulty;
};

UbxWeekCase ubxWeekCase(std::size_t rawx_index, const PppConfig& config) {
  UbxWeekCase c;
  c.bytes = ubxWithBadWeek(rawx_index, c.offset);
  c.path = writeTemp("ubx_week", "gnss_1730_badweek.ubx", c.bytes);
  c.clean = solve(ubxWalk(), ObservationFormat::Ubx, config);
  c.faulty = solve(c.path, ObservationFormat::Ubx, config);
  return c;
}

// ---------------------------------------------------------------------------
TEST(IntegrityTime, OneUbxEpochWithItsWeekOneTooHighCostsThatEpochOnly) {
  PPP_REQUIRE_SHARED_DATA();
  const PppConfig config = ubxConfig();
  const UbxWeekCase c = ubxWeekCase(200, config);
  const std::size_t offset = c.offset;
  const Bytes& bad_bytes = c.bytes;
  const std::string& bad = c.path;
  const PppSolveOutcome& clean = c.clean;
  const PppSolveOutcome& faulty = c.faulty;
  EXPECT_EQ(clean.run.epochs_read, 536u);  // RXM-RAWX epochs (data README)
  expectOnlyTheBadEpochLost("ubx week+1 at byte " + std::to_string(offset), clean, faulty);  // before: 18 of 338
  EXPECT_TRUE(anyContains(faulty.run.problems, "byte " + std::to_string(offset), "isolated time jump"));

  // Live: the same epochs, the outlier counted with its reason, no restart.
  UbxObservationSource offline(bad);
  const std::vector<GnssTime> offline_times = offlineTimes(offline);
  EXPECT_EQ(offline.timeScreen().count(StreamProblemKind::EpochTimeRefused), 1u);
  const LiveOutcome live = runLive(bad_bytes, StreamFormat::Ubx, &config);
  EXPECT_EQ(live.times, offline_times);
  const LiveStreamStatus& s = observationStatus(live);
  EXPECT_EQ(s.time_outliers, 1u);
  EXPECT_EQ(s.restarts, 0u);
  EXPECT_EQ(s.time_backwards, 0u);
  EXPECT_EQ(s.problems.count(StreamProblemKind::EpochTimeRefused), 1u);
  EXPECT_GE(live.solved + 1, clean.run.epochs_solved);
  EXPECT_TRUE(anyContains(live.time_events, "byte " + std::to_string(offset), "isolated time jump"));
  std::printf("live: %zu epochs, %zu solved, %llu outlier(s), %llu restart(s)\n", live.times.size(), live.solved,
              static_cast<unsigned long long>(s.time_outliers), static_cast<unsigned long long>(s.restarts));
}

TEST(IntegrityTime, ABadFirstUbxEpochCostsThatEpochOnly) {
  // The first epoch is not believed alone: the start-up waits for a time line.
  PPP_REQUIRE_SHARED_DATA();
  const UbxWeekCase c = ubxWeekCase(0, ubxConfig());
  expectOnlyTheBadEpochLost("ubx first epoch week+1", c.clean, c.faulty);
  UbxObservationSource offline(c.path);
  const LiveOutcome live = runLive(c.bytes, StreamFormat::Ubx, nullptr);
  EXPECT_EQ(live.times, offlineTimes(offline));
  EXPECT_EQ(observationStatus(live).time_outliers, 1u);
  EXPECT_EQ(observationStatus(live).restarts, 0u);
}

TEST(IntegrityTime, OneRtcmFrameTwoDaysAheadCostsThatFrameOnlyOfflineAndLive) {
  PPP_REQUIRE_SHARED_DATA();
  std::size_t offset = 0;
  const Bytes bad_bytes = rtcmWithTowAhead(299, 2.0, offset);
  const std::string bad = writeTemp("rtcm_tow", "str24_tow2d.rtcm3", bad_bytes);
  const PppConfig config;

  const PppSolveOutcome clean = solve(str24(), ObservationFormat::Rtcm3, config);
  const PppSolveOutcome faulty = solve(bad, ObservationFormat::Rtcm3, config);
  std::printf("rtcm 1074 +2 d at byte %zu: clean %zu read %zu solved; faulty %zu read %zu solved %zu refused\n",
              offset, clean.run.epochs_read, clean.run.epochs_solved, faulty.run.epochs_read, faulty.run.epochs_solved,
              faulty.run.epochs_refused);
  EXPECT_EQ(faulty.run.epochs_refused, 0u);  // before: 834 of 1,133
  EXPECT_GE(faulty.run.epochs_solved + 1, clean.run.epochs_solved);
  EXPECT_TRUE(anyContains(faulty.run.problems, "byte " + std::to_string(offset), "isolated time jump"));

  RtcmObservationSource offline(bad);
  const std::vector<GnssTime> offline_times = offlineTimes(offline);
  EXPECT_EQ(offline.timeScreen().count(StreamProblemKind::EpochTimeRefused), 1u);
  EXPECT_TRUE(std::is_sorted(offline_times.begin(), offline_times.end()));
  const LiveOutcome live = runLive(bad_bytes, StreamFormat::Rtcm3, nullptr);
  EXPECT_EQ(live.times, offline_times);  // offline and live agree
  const LiveStreamStatus& s = observationStatus(live);
  EXPECT_EQ(s.time_outliers, 1u);
  EXPECT_EQ(s.restarts, 0u);  // before: a receiver restart
  ASSERT_EQ(live.time_events.size(), 1u);
  EXPECT_NE(live.time_events[0].find("byte " + std::to_string(offset)), std::string::npos) << live.time_events[0];
}

TEST(IntegrityTime, StaleSsrFallsBackToBroadcastWithoutItsBiases) {
  PPP_REQUIRE_SHARED_DATA();
  const PppConfig config = ubxConfig();
  const PppSolveOutcome without = solve(ubxWalk(), ObservationFormat::Ubx, config);
  const PppSolveOutcome stale = solve(ubxWalk(), ObservationFormat::Ubx, config, staleSsr());
  std::printf("stale SSR: without the stream %zu solved, with it %zu solved\n", without.run.epochs_solved,
              stale.run.epochs_solved);
  EXPECT_GT(without.run.epochs_solved, 300u);
  EXPECT_EQ(stale.run.epochs_solved, without.run.epochs_solved);  // before: 0 of 536
  EXPECT_TRUE(anyContains(stale.run.notes, "broadcast fallback", "s old"));
  // No satellite is left out for a missing SSR bias ("no OSB ..."): the signal stage rejects what it did without SSR.
  const RejectionKey signals{RejectionStage::Signals, RejectionReason::SignalSelection};
  auto count = [&](const PppRunSummary& r) {
    const auto it = r.rejection_counts.find(signals);
    return it == r.rejection_counts.end() ? std::size_t{0} : it->second;
  };
  EXPECT_EQ(count(stale.run), count(without.run));

  // Live: the node's path with the same stream: broadcast only, its biases have no say, epochs solved.
  const Bytes obs = readBytes(ubxWalk());
  const Bytes ssr = readBytes(staleSsr());
  const LiveOutcome live = runLive(obs, StreamFormat::Ubx, &config, &ssr, /*expect_corrections=*/true);
  std::printf("live with the stale stream: %zu epochs, %zu broadcast only, %zu solved\n", live.times.size(),
              live.broadcast_only, live.solved);
  EXPECT_EQ(live.broadcast_only, live.times.size());
  EXPECT_FALSE(live.ssr_biases_applied);
  EXPECT_GE(live.solved + 5, without.run.epochs_solved);  // before: 0
}

TEST(IntegrityTime, ARefDateOneWeekOffIsRefusedNamingTheDateAndTheEvidence) {
  PPP_REQUIRE_SHARED_DATA();
  Rtcm3DecoderOptions right;
  right.reference_time = parseReferenceDate("2018/07/14");
  EXPECT_NO_THROW(RtcmObservationSource(str24(), right));
  for (const std::string date : {"2018/07/21", "2018/07/07"}) {
    Rtcm3DecoderOptions wrong;
    wrong.reference_time = parseReferenceDate(date);
    try {
      RtcmObservationSource source(str24(), wrong);
      ADD_FAILURE() << date << " accepted";
    } catch (const ParseError& e) {
      const std::string what = e.what();
      std::printf("%s: %s\n", date.c_str(), what.c_str());
      EXPECT_NE(what.find(date), std::string::npos) << what;
      EXPECT_NE(what.find("ephemerides"), std::string::npos) << what;
      EXPECT_NE(what.find("7."), std::string::npos) << what;  // a week: 7.x days
      EXPECT_NE(what.find("week-rollover-STR24.rtcm3"), std::string::npos) << what;
    }
  }
  // Live (the nodes' ros.live reference date): said in the stream status and once as an event.
  const Bytes bytes = readBytes(str24());
  const LiveOutcome live_wrong = runLive(bytes, StreamFormat::Rtcm3, nullptr, nullptr, false, parseReferenceDate("2018/07/21"));
  const LiveOutcome live_right = runLive(bytes, StreamFormat::Rtcm3, nullptr, nullptr, false, parseReferenceDate("2018/07/14"));
  EXPECT_NE(observationStatus(live_wrong).reference_date_warning.find("2018/07/21"), std::string::npos);
  EXPECT_TRUE(anyContains(live_wrong.time_events, "2018/07/21", "ephemerides"));
  EXPECT_EQ(observationStatus(live_right).reference_date_warning, "");
  EXPECT_TRUE(live_right.time_events.empty());
}

TEST(IntegrityTime, BroadcastUraIsTheNominalValueOfItsIndex) {
  // IS-GPS-200 20.3.3.3.1.1 (nominal URA), as RINEX and RTKLIB convbin write it.
  const double nominal[16] = {2.0, 2.8, 4.0, 5.7, 8.0, 11.3, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0, 1024.0, 2048.0,
                              4096.0, 8192.0};
  for (int i = 0; i < 16; ++i) {
    EXPECT_DOUBLE_EQ(gpsUra_m(i), nominal[i]) << i;
    EXPECT_EQ(gpsUraIndex(gpsUra_m(i)), i) << i;  // the encoders give the index back
  }
  EXPECT_EQ(gpsUraIndex(4.85), 2);  // an upper-bound value still reads as its index
  PPP_REQUIRE_SHARED_DATA();
  RtcmObservationSource source(str24());
  const Rtcm3Output& nav = source.scanNavigation();
  const std::set<double> allowed(std::begin(nominal), std::end(nominal));
  std::size_t gps_index2 = 0, qzss_index2 = 0, qzss = 0;
  for (const auto& e : nav.gps) {
    EXPECT_TRUE(allowed.count(e.ura_m)) << e.satellite.toString() << " " << e.ura_m;
    const bool q = e.satellite.system == GnssSystem::QZSS;
    if (e.ura_m == 4.0) ++(q ? qzss_index2 : gps_index2);
    if (q) {
      ++qzss;
      EXPECT_EQ(e.l2p_data_flag, 1) << e.satellite.toString();  // IS-QZSS-PNT: fixed to 1
    }
  }
  std::printf("STR24: %zu GPS and %zu QZSS records with URA index 2 (4.0 m), %zu QZSS records\n", gps_index2,
              qzss_index2, qzss);
  EXPECT_GE(gps_index2, 31u);  // convbin writes 4.0 m for these
  EXPECT_GE(qzss_index2, 2u);
}

}  // namespace
}  // namespace ppp
