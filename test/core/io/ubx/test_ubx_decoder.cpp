// UbxFramer / UbxDecoder / UbxObservationSource: framing in any chunking,
// Fletcher checksum, resynchronisation, bad length, truncation; RXM-RAWX flags
// and lock-time logic on built messages; and the real recording gnss_1730.ubx
// against RTKLIB convbin (Debian rtklib 2.4.3 b34, run here into a temp dir):
// every observation of the signals convbin decodes, to the printed precision,
// and the ephemerides (positions 1 mm, clocks 0.01 ns).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/observation_source.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/ubx/ubx_decoder.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "ppp_bayes_tree/models/broadcast_ephemeris.h"
#include "fuzz/ubx_fuzz_entry.h"
#include "test_support.h"

namespace ppp {
namespace {

const char* kUbxFile = "streams/ubx/gnss_1730.ubx";

std::vector<UbxFrame> frameAll(const std::vector<std::uint8_t>& bytes, std::size_t chunk, UbxFramer& framer) {
  std::vector<UbxFrame> frames;
  for (std::size_t i = 0; i < bytes.size(); i += chunk) {
    framer.feed(bytes.data() + i, std::min(chunk, bytes.size() - i), [&](const UbxFrame& f) { frames.push_back(f); });
  }
  framer.finish();
  return frames;
}

void append(std::vector<std::uint8_t>& out, const std::vector<std::uint8_t>& more) {
  out.insert(out.end(), more.begin(), more.end());
}

TEST(UbxFramer, ChecksumOfAKnownFrame) {
  // UBX-ACK-ACK for CFG-PRT: B5 62 05 01 02 00 06 00 -> CK 0E 37 (interface description 3.4 algorithm;
  // the frame as printed in u-blox application notes).
  const auto frame = encodeUbxFrame(0x05, 0x01, {0x06, 0x00});
  ASSERT_EQ(frame.size(), 10u);
  EXPECT_EQ(frame[8], 0x0E);
  EXPECT_EQ(frame[9], 0x37);
}

TEST(UbxFramer, AnyChunkingGarbageChecksumErrorsAndTruncation) {
  std::vector<std::uint8_t> stream;
  const std::string nmea = "$GNGGA,173040.00,,,,,0,00,99.99,,,,,,*7A\r\n";
  stream.insert(stream.end(), nmea.begin(), nmea.end());                        // NMEA text, not a problem
  append(stream, encodeUbxFrame(0x01, 0x07, std::vector<std::uint8_t>(92, 7)));  // good NAV-PVT
  auto bad = encodeUbxFrame(0x02, 0x15, std::vector<std::uint8_t>(16, 1));
  bad[10] ^= 0x40;  // payload byte flipped: checksum error
  append(stream, bad);
  append(stream, {0xB5, 0x62, 0x02, 0x13, 0xFF, 0xFF});                         // length 65535: bad length
  append(stream, encodeUbxFrame(0x02, 0x13, std::vector<std::uint8_t>(8, 0)));   // good
  append(stream, {0xB5, 0x00});                                                   // false sync
  append(stream, encodeUbxFrame(0x0A, 0x04, {}));                                 // good, empty payload
  append(stream, {0xB5, 0x62, 0x02, 0x15, 0x10, 0x00, 1, 2});  // truncated at the end
  for (std::size_t chunk : {std::size_t{1}, std::size_t{3}, std::size_t{7}, std::size_t{64}, stream.size()}) {
    UbxFramer framer;
    const auto frames = frameAll(stream, chunk, framer);
    ASSERT_EQ(frames.size(), 3u) << "chunk " << chunk;
    EXPECT_EQ(frames[0].messageType(), 0x0107);
    EXPECT_EQ(frames[0].payload.size(), 92u);
    EXPECT_EQ(frames[0].byte_offset, nmea.size());
    EXPECT_EQ(frames[1].messageType(), 0x0213);
    EXPECT_EQ(frames[2].messageType(), 0x0A04);
    EXPECT_EQ(frames[2].frame_index, 2u);
    const StreamCounters& c = framer.counters();
    EXPECT_EQ(c.bytes, stream.size());
    EXPECT_EQ(c.count(StreamProblemKind::ChecksumError), 1u);
    EXPECT_EQ(c.count(StreamProblemKind::BadLength), 1u);
    EXPECT_EQ(c.count(StreamProblemKind::TruncatedFrame), 1u);
    EXPECT_GE(c.count(StreamProblemKind::Garbage), 1u);  // the damaged frame's and the false sync's bytes
    EXPECT_EQ(c.nmea_bytes, nmea.size());
    for (const auto& p : c.problems) EXPECT_GT(p.byte_offset, nmea.size() - 1) << p.describe();
    EXPECT_EQ(c.frames_by_type.at(0x0107), 1u);
    // Every problem names its byte offset: the checksum error is at the RAWX frame.
    for (const auto& p : c.problems) {
      if (p.kind == StreamProblemKind::ChecksumError) {
        EXPECT_EQ(p.byte_offset, nmea.size() + 100u);
        EXPECT_EQ(p.message_type, 0x0215);
        EXPECT_NE(p.describe().find("byte " + std::to_string(nmea.size() + 100)), std::string::npos);
      }
    }
  }
}

// One RXM-RAWX measurement block (interface description UBX-RXM-RAWX layout).
std::vector<std::uint8_t> rawxMeasurement(double pr, double cp, float dop, int gnss, int sv, int sig, int lock_ms,
                                          int cn0, int cp_stdev, int trk) {
  std::vector<std::uint8_t> m(32, 0);
  std::memcpy(m.data(), &pr, 8);
  std::memcpy(m.data() + 8, &cp, 8);
  std::memcpy(m.data() + 16, &dop, 4);
  m[20] = static_cast<std::uint8_t>(gnss);
  m[21] = static_cast<std::uint8_t>(sv);
  m[22] = static_cast<std::uint8_t>(sig);
  m[23] = 7;
  m[24] = static_cast<std::uint8_t>(lock_ms & 0xFF);
  m[25] = static_cast<std::uint8_t>(lock_ms >> 8);
  m[26] = static_cast<std::uint8_t>(cn0);
  m[28] = static_cast<std::uint8_t>(cp_stdev);
  m[30] = static_cast<std::uint8_t>(trk);
  return m;
}

std::vector<std::uint8_t> rawx(double tow, int week, const std::vector<std::vector<std::uint8_t>>& meas) {
  std::vector<std::uint8_t> p(16, 0);
  std::memcpy(p.data(), &tow, 8);
  p[8] = static_cast<std::uint8_t>(week & 0xFF);
  p[9] = static_cast<std::uint8_t>(week >> 8);
  p[10] = 18;
  p[11] = static_cast<std::uint8_t>(meas.size());
  p[12] = 0x01;
  p[13] = 1;
  for (const auto& m : meas) append(p, m);
  return encodeUbxFrame(0x02, 0x15, p);
}

TEST(UbxDecoder, RawxValidityFlagsAndLossOfLock) {
  std::vector<std::uint8_t> s;
  // Epoch 1: G05 L1C/A all valid, half cycle resolved; E11 E1C phase invalid; an unmapped sigId.
  append(s, rawx(100.0, 2381,
                 {rawxMeasurement(2.0e7, 1.05e8, -100.5f, 0, 5, 0, 5000, 45, 2, 0x07),
                  rawxMeasurement(2.3e7, 1.2e8, 50.0f, 2, 11, 0, 3000, 40, 2, 0x01),
                  rawxMeasurement(2.3e7, 1.2e8, 50.0f, 2, 11, 2, 3000, 40, 2, 0x03)}));
  // Epoch 2: G05 lock time went down (slip); E11 phase valid, half cycle not resolved, cpStdev 6 (dropped).
  append(s, rawx(100.25, 2381,
                 {rawxMeasurement(2.0e7, 1.05e8, -100.5f, 0, 5, 0, 100, 45, 2, 0x07),
                  rawxMeasurement(2.3e7, 1.2e8, 50.0f, 2, 11, 0, 3250, 40, 6, 0x03)}));
  // Epoch 3: G05 lock grows, but the half-cycle-subtracted flag changes (slip); E11 cpStdev 2, no half cycle.
  append(s, rawx(100.5, 2381,
                 {rawxMeasurement(2.0e7, 1.05e8, -100.5f, 0, 5, 0, 350, 45, 2, 0x0F),
                  rawxMeasurement(2.3e7, 1.2e8, 50.0f, 2, 11, 0, 3500, 40, 2, 0x03)}));
  // Same time again: refused.
  append(s, rawx(100.5, 2381, {}));
  append(s, encodeUbxFrame(0x7F, 0x01, {1, 2, 3}));  // not a UBX class
  UbxDecoder decoder;
  std::vector<UbxObservationEpoch> epochs;
  UbxDecoder::Handlers h;
  h.on_epoch = [&](const UbxObservationEpoch& e) { epochs.push_back(e); };
  decoder.feed(s.data(), s.size(), h);
  decoder.finish();
  ASSERT_EQ(epochs.size(), 3u);
  EXPECT_EQ(epochs[0].time, GnssTime::fromGpsWeek(2381, 100.0));
  ASSERT_EQ(epochs[0].leap_seconds.value_or(0), 18);
  ASSERT_EQ(epochs[0].measurements.size(), 2u);
  const auto& g1 = epochs[0].measurements[0];
  EXPECT_EQ(g1.satellite.toString(), "G05");
  EXPECT_EQ(g1.signal.signal(), "1C");
  EXPECT_EQ(g1.carrier_phase_cycles.value_or(0), 1.05e8);
  EXPECT_EQ(g1.lli, kLliLossOfLock);  // first sight: a new arc
  const auto& e1 = epochs[0].measurements[1];
  EXPECT_EQ(e1.satellite.toString(), "E11");
  EXPECT_TRUE(e1.pseudorange_m.has_value());
  EXPECT_FALSE(e1.carrier_phase_cycles.has_value());
  EXPECT_EQ(decoder.statistics().unmapped_signals.at({2, 2}), 1u);
  EXPECT_EQ(epochs[1].measurements[0].lli & kLliLossOfLock, kLliLossOfLock);
  EXPECT_FALSE(epochs[1].measurements[1].carrier_phase_cycles.has_value());  // cpStdev 6 > 5
  // E11: first sight at epoch 1 without a phase; that flag is not held (its lock time grows).
  EXPECT_EQ(epochs[1].measurements[1].lli, kLliHalfCycle);
  EXPECT_EQ(epochs[2].measurements[0].lli, kLliLossOfLock);
  EXPECT_EQ(epochs[2].measurements[1].lli, kLliHalfCycle);
  EXPECT_TRUE(epochs[2].measurements[1].carrier_phase_cycles.has_value());
  EXPECT_TRUE(epochs[2].measurements[1].carrier_phase_cycles.has_value());
  EXPECT_EQ(decoder.counters().count(StreamProblemKind::UnknownMessage), 1u);
  EXPECT_EQ(decoder.counters().count(StreamProblemKind::MalformedMessage), 1u);  // time not after previous
}

TEST(UbxDecoder, SignalMapFollowsTheInterfaceDescription) {
  EXPECT_EQ(ubxSignalCode(0, 3)->signal(), "2L");
  EXPECT_EQ(ubxSignalCode(2, 4)->signal(), "5Q");
  EXPECT_EQ(ubxSignalCode(3, 5)->signal(), "1P");
  EXPECT_EQ(ubxSignalCode(3, 7)->signal(), "5P");
  EXPECT_EQ(ubxSignalCode(3, 0)->signal(), "2I");
  EXPECT_FALSE(ubxSignalCode(0, 1).has_value());
  EXPECT_EQ(ubxSatellite(1, 133)->toString(), "S33");
  EXPECT_FALSE(ubxSatellite(6, 255).has_value());
}

// ----------------------------------------------------------------------------
// The real recording against convbin.

struct ConvbinOutput {
  std::filesystem::path obs, nav;
};

std::optional<ConvbinOutput> runConvbin(std::string& why) {
  if (std::system("command -v convbin > /dev/null 2>&1") != 0) {
    why = "RTKLIB convbin not installed (Debian package rtklib)";
    return std::nullopt;
  }
  const auto dir = test::tempDir("ubx_convbin");
  ConvbinOutput out{dir / "gnss_1730.obs", dir / "gnss_1730.nav"};
  const std::string cmd = "convbin -r ubx -od -os -o " + out.obs.string() + " -n " + out.nav.string() + " " +
                          test::dataPath(kUbxFile) + " > " + (dir / "convbin.log").string() + " 2>&1";
  if (std::system(cmd.c_str()) != 0 || !std::filesystem::exists(out.obs)) {
    why = "convbin failed: " + cmd;
    return std::nullopt;
  }
  return out;
}

bool ubxDataAvailable() { return std::filesystem::exists(test::dataPath(kUbxFile)); }

TEST(UbxRealData, FramesAndCountsOfTheRecording) {
  if (!ubxDataAvailable()) GTEST_SKIP() << "UBX recording not found at " << test::dataPath(kUbxFile);
  UbxObservationSource source(test::dataPath(kUbxFile));
  const StreamCounters& c = source.counters();
  // README of ../shared/data/streams: 536 RXM-RAWX, 2,328 RXM-SFRBX and NAV-PVT (one per epoch).
  EXPECT_EQ(c.frames_by_type.at(0x0215), 536u);
  EXPECT_EQ(c.frames_by_type.at(0x0213), 2328u);
  EXPECT_EQ(c.frames_by_type.at(0x0107), 536u);
  EXPECT_EQ(c.count(StreamProblemKind::ChecksumError), 0u);
  EXPECT_EQ(c.count(StreamProblemKind::UnknownMessage), 0u);
  EXPECT_EQ(source.statistics().known_not_used, 536u);
  EXPECT_EQ(source.decodedEpochs().size(), 536u);
  // Every RAWX signal of the recording is in the map (README: GPS L1C/A, L2CL, L5Q; Galileo E1C,
  // E5aQ, E6; BeiDou B3I, B1Cp, B2ap; SBAS L1).
  EXPECT_TRUE(source.statistics().unmapped_signals.empty());
  std::set<std::string> signals;
  for (int s = 0; s < kNumGnssSystems; ++s) {
    for (const auto& code : source.header().obs_types[s]) {
      if (code.type == ObservableType::Pseudorange)
        signals.insert(std::string(1, systemLetter(static_cast<GnssSystem>(s))) + code.signal());
    }
  }
  EXPECT_EQ(signals, (std::set<std::string>{"G1C", "G2L", "G5Q", "E1C", "E5Q", "E6B", "C6I", "C1P", "C5P", "S1C"}));
  std::printf("NMEA bytes between UBX frames: %llu; other garbage: %llu bytes in %llu runs\n",
              static_cast<unsigned long long>(c.nmea_bytes), static_cast<unsigned long long>(c.garbage_bytes),
              static_cast<unsigned long long>(c.count(StreamProblemKind::Garbage)));
  // The recording interleaves NMEA (u-blox default output): text, not damage.
  EXPECT_GT(c.nmea_bytes, 100000u);
  EXPECT_EQ(c.count(StreamProblemKind::Garbage), 0u);
  std::printf("ephemerides from SFRBX: %zu GPS, %zu Galileo; inconsistent IOD %llu\n", source.navigation().gps.size(),
              source.navigation().galileo.size(),
              static_cast<unsigned long long>(c.count(StreamProblemKind::InconsistentEphemeris)));
}

TEST(UbxRealData, ObservationsEqualConvbin) {
  if (!ubxDataAvailable()) GTEST_SKIP() << "UBX recording not found at " << test::dataPath(kUbxFile);
  std::string why;
  const auto convbin = runConvbin(why);
  if (!convbin) GTEST_SKIP() << why;
  UbxObservationSource ours(test::dataPath(kUbxFile));
  RinexObservationSource peer(convbin->obs.string());
  std::map<std::int64_t, ObsEpoch> our_epochs;  // by time in 100 ns
  auto key = [](const GnssTime& t) {
    return static_cast<std::int64_t>(std::llround((t - GnssTime::fromGpsWeek(2381, 0.0)) * 1e7));
  };
  {
    ObsEpoch e;
    while (ours.next(e) == ObservationRead::Epoch) our_epochs[key(e.time)] = e;
  }
  std::size_t epochs = 0, compared = 0, lli_compared = 0, blank_doppler = 0, peer_sats = 0;
  std::size_t failures = 0;
  ObsEpoch theirs;
  while (peer.next(theirs) == ObservationRead::Epoch) {
    ++epochs;
    const auto it = our_epochs.find(key(theirs.time));
    ASSERT_NE(it, our_epochs.end()) << "convbin epoch " << theirs.time.toString() << " not decoded";
    const ObsEpoch& mine = it->second;
    for (std::size_t i = 0; i < theirs.satellites.size(); ++i) {
      const SatelliteId sat = theirs.satellites[i].satellite;
      ++peer_sats;
      for (const Observation* o = theirs.begin(i); o != theirs.end(i); ++o) {
        const Observation* m = mine.find(sat, o->code);
        const std::string where = theirs.time.toString() + " " + sat.toString() + " " + o->code.toString();
        const bool mine_present = m != nullptr && m->value.has_value();
        if (!o->value) {
          // convbin writes 0.0 as blank: a Doppler of exactly 0 Hz.
          if (o->code.type == ObservableType::Doppler && mine_present && *m->value == 0.0) {
            ++blank_doppler;
            continue;
          }
          if (mine_present && ++failures < 20) ADD_FAILURE() << where << ": convbin blank, ours " << *m->value;
          continue;
        }
        if (!mine_present) {
          if (++failures < 20) ADD_FAILURE() << where << ": ours missing, convbin " << *o->value;
          continue;
        }
        ++compared;
        // Printed precision: %14.3f (RTKLIB outrnxobsf), so 0.0005 plus the double's rounding.
        if (std::abs(*m->value - *o->value) > 0.0005 + 1e-9 && ++failures < 20)
          ADD_FAILURE() << where << ": ours " << *m->value << " convbin " << *o->value;
        if (o->code.type == ObservableType::CarrierPhase) {
          ++lli_compared;
          if (m->lli.value_or(0) != o->lli.value_or(0) && ++failures < 20)
            ADD_FAILURE() << where << ": LLI ours " << int(m->lli.value_or(0)) << " convbin " << int(o->lli.value_or(0));
        }
      }
    }
    // Every satellite we have with a convbin signal is in convbin's epoch too.
    for (std::size_t i = 0; i < mine.satellites.size(); ++i) {
      const SatelliteId sat = mine.satellites[i].satellite;
      bool has_peer_signal = false;
      for (const Observation* o = mine.begin(i); o != mine.end(i); ++o) {
        for (const auto& code : peer.header().types(sat.system))
          if (code == o->code && o->value) has_peer_signal = true;
      }
      if (has_peer_signal && !theirs.indexOf(sat) && ++failures < 20)
        ADD_FAILURE() << theirs.time.toString() << " " << sat.toString() << " decoded, not in convbin's epoch";
    }
  }
  EXPECT_EQ(failures, 0u);
  EXPECT_EQ(epochs, 536u);
  std::printf("UBX vs convbin: %zu epochs, %zu satellite records, %zu values equal to the printed precision, "
              "%zu phase LLIs equal, %zu zero Dopplers (blank in convbin)\n",
              epochs, peer_sats, compared, lli_compared, blank_doppler);
  EXPECT_GT(compared, 45000u);  // 46,637 values at the time of writing
}

TEST(UbxRealData, EphemeridesEqualConvbin) {
  if (!ubxDataAvailable()) GTEST_SKIP() << "UBX recording not found at " << test::dataPath(kUbxFile);
  std::string why;
  const auto convbin = runConvbin(why);
  if (!convbin) GTEST_SKIP() << why;
  UbxObservationSource ours(test::dataPath(kUbxFile));
  const NavData peer = readRinexNav(convbin->nav.string());
  std::size_t gps = 0, galileo = 0;
  double max_pos = 0.0, max_clk = 0.0;
  auto compare = [&](const BroadcastState& a, const BroadcastState& b, const std::string& what) {
    const double dp = (a.position_ecef_m - b.position_ecef_m).norm();
    const double dc = std::abs(a.clock_bias_s - b.clock_bias_s) * 1e9;
    max_pos = std::max(max_pos, dp);
    max_clk = std::max(max_clk, dc);
    EXPECT_LT(dp, 1e-3) << what;
    EXPECT_LT(dc, 0.01) << what;
  };
  for (const auto& p : peer.gps) {
    const GpsLnavEphemeris* mine = nullptr;
    for (const auto& m : ours.navigation().gps)
      if (m.satellite == p.satellite && m.iode == p.iode && m.orbit.toe == p.orbit.toe) mine = &m;
    ASSERT_NE(mine, nullptr) << "convbin's " << p.satellite.toString() << " IODE " << p.iode << " not decoded";
    EXPECT_EQ(mine->iodc, p.iodc);
    EXPECT_EQ(mine->health, p.health);
    EXPECT_NEAR(mine->tgd_s, p.tgd_s, 1e-20);  // RINEX prints 12 digits
    for (double dt : {-7200.0, -1800.0, 0.0, 1800.0, 7200.0})
      compare(satelliteState(*mine, p.orbit.toe + dt), satelliteState(p, p.orbit.toe + dt),
              p.satellite.toString() + " dt " + std::to_string(dt));
    ++gps;
  }
  for (const auto& p : peer.galileo) {
    const GalileoEphemeris* mine = nullptr;
    for (const auto& m : ours.navigation().galileo)
      if (m.satellite == p.satellite && m.iod_nav == p.iod_nav && m.orbit.toe == p.orbit.toe) mine = &m;
    ASSERT_NE(mine, nullptr) << "convbin's " << p.satellite.toString() << " IOD " << p.iod_nav << " not decoded";
    EXPECT_EQ(mine->health, p.health);
    EXPECT_DOUBLE_EQ(mine->bgd_e5a_e1_s, p.bgd_e5a_e1_s);
    for (double dt : {-7200.0, -1800.0, 0.0, 1800.0, 7200.0})
      compare(satelliteState(*mine, p.orbit.toe + dt), satelliteState(p, p.orbit.toe + dt),
              p.satellite.toString() + " dt " + std::to_string(dt));
    ++galileo;
  }
  std::printf("SFRBX ephemerides vs convbin: %zu GPS and %zu Galileo records matched (ours: %zu GPS, %zu Galileo); "
              "max position difference %.2e m, max clock difference %.2e ns over toe-2h..toe+2h\n",
              gps, galileo, ours.navigation().gps.size(), ours.navigation().galileo.size(), max_pos, max_clk);
  EXPECT_EQ(gps, 4u);  // convbin: G10, G23, G27, G32 (the walk is 2 min long)
  // Differs by design: convbin 2.4.3 b34 writes no Galileo record from this file (it waits
  // for all I/NAV word types 0-6 of one satellite, GST-UTC word 6 included); we release a
  // record with words 1-5 (OS SIS ICD 4.3.5: 1-4 carry the ephemeris and clock, 5 the
  // week, BGDs and health). Our Galileo records are checked by the broadcast walk
  // (test_ubx_walk): single-point residuals at the metre level.
  if (peer.galileo.empty()) {
    std::printf("convbin wrote no Galileo record; ours: %zu (checked by the walk)\n", ours.navigation().galileo.size());
  } else {
    EXPECT_GT(galileo, 0u);
  }
}


// ----------------------------------------------------------------------------
// The generated seed corpus (test/fuzz/make_ubx_corpus.py): the SFRBX decoders on
// known field values, and the fuzz entry over every seed.

std::vector<std::uint8_t> seed(const std::string& name) {
  const std::string bytes = test::readFileBytes(std::string(PPP_FUZZ_DIR) + "/corpus/ubx/" + name);
  return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
}

TEST(UbxGeneratedSeeds, LnavAndInavFieldsDecodeToTheirValues) {
  std::vector<GpsLnavEphemeris> gps;
  std::vector<GalileoEphemeris> galileo;
  UbxDecoder::Handlers h;
  h.on_gps = [&](const GpsLnavEphemeris& e) { gps.push_back(e); };
  h.on_galileo = [&](const GalileoEphemeris& e) { galileo.push_back(e); };
  for (const char* name : {"lnav_frame.ubx", "inav_words.ubx"}) {
    UbxDecoder decoder;
    const auto bytes = seed(name);
    decoder.feed(bytes.data(), bytes.size(), h);
    decoder.finish();
    EXPECT_EQ(decoder.counters().totalProblems(), 0u) << name;
  }
  // Values written by make_ubx_corpus.py (its docstring).
  ASSERT_EQ(gps.size(), 1u);
  EXPECT_EQ(gps[0].satellite.toString(), "G07");
  EXPECT_EQ(gps[0].iodc, 0x14D);
  EXPECT_EQ(gps[0].iode, 0x4D);
  EXPECT_DOUBLE_EQ(gps[0].orbit.sqrt_a_sqrtm, 5153.5);
  EXPECT_EQ(gps[0].orbit.toe, GnssTime::fromGpsWeek(2381, 410400.0));
  EXPECT_EQ(gps[0].clock.toc, GnssTime::fromGpsWeek(2381, 410400.0));
  EXPECT_DOUBLE_EQ(gps[0].tgd_s, -4.0 * std::ldexp(1.0, -31));
  EXPECT_DOUBLE_EQ(gps[0].clock.af0_s, 123456.0 * std::ldexp(1.0, -31));
  EXPECT_DOUBLE_EQ(gps[0].orbit.omega_dot_radps, -20000.0 * std::ldexp(1.0, -43) * 3.1415926535898);
  EXPECT_DOUBLE_EQ(gps[0].orbit.m0_rad, 1234567890.0 * std::ldexp(1.0, -31) * 3.1415926535898);
  ASSERT_EQ(galileo.size(), 1u);
  EXPECT_EQ(galileo[0].satellite.toString(), "E11");
  EXPECT_EQ(galileo[0].iod_nav, 77);
  EXPECT_DOUBLE_EQ(galileo[0].orbit.sqrt_a_sqrtm, 5440.5);
  EXPECT_EQ(galileo[0].orbit.toe, GnssTime::fromGpsWeek(2381, 410400.0));
  EXPECT_DOUBLE_EQ(galileo[0].clock.af0_s, -2000000.0 * std::ldexp(1.0, -34));
  EXPECT_DOUBLE_EQ(galileo[0].bgd_e5a_e1_s, 7.0 * std::ldexp(1.0, -32));
  EXPECT_DOUBLE_EQ(galileo[0].bgd_e5b_e1_s.value_or(0), 8.0 * std::ldexp(1.0, -32));
  EXPECT_NEAR(galileo[0].sisa_m.value_or(0), 2.0 + 7 * 0.16, 1e-12);  // index 107 (OS SIS ICD table 89)
}

TEST(UbxGeneratedSeeds, InconsistentIodAndCorruptPagesAreCounted) {
  // The LNAV frame with subframe 3's IODE changed: one InconsistentEphemeris, no record.
  auto bytes = seed("lnav_frame.ubx");
  UbxDecoder probe;
  std::vector<std::uint64_t> offsets;
  UbxFramer framer;
  framer.feed(bytes.data(), bytes.size(), [&](const UbxFrame& f) { offsets.push_back(f.byte_offset); });
  ASSERT_EQ(offsets.size(), 4u);  // RAWX + subframes 1-3
  // Subframe 3 is the last frame: its word 10 holds IODE in data bits 1-8 (ICD bits 271-278).
  const std::size_t word10 = offsets[3] + 6 + 8 + 4 * 9;
  std::uint32_t w = bytes[word10] | (bytes[word10 + 1] << 8) | (bytes[word10 + 2] << 16) |
                    (static_cast<std::uint32_t>(bytes[word10 + 3]) << 24);
  w ^= 0x01u << 22;  // flip an IODE bit
  for (int k = 0; k < 4; ++k) bytes[word10 + k] = static_cast<std::uint8_t>(w >> (8 * k));
  const auto frame3 = encodeUbxFrame(0x02, 0x13,
                                     std::vector<std::uint8_t>(bytes.begin() + offsets[3] + 6, bytes.end() - 2));
  std::copy(frame3.begin(), frame3.end(), bytes.begin() + offsets[3]);
  std::size_t records = 0;
  UbxDecoder::Handlers h;
  h.on_gps = [&](const GpsLnavEphemeris&) { ++records; };
  probe.feed(bytes.data(), bytes.size(), h);
  EXPECT_EQ(records, 0u);
  EXPECT_EQ(probe.counters().count(StreamProblemKind::InconsistentEphemeris), 1u);
  // An I/NAV page with a flipped data bit (checksum re-made for the frame): a CRC-24Q failure.
  auto inav = seed("inav_words.ubx");
  UbxFramer framer2;
  std::vector<UbxFrame> frames;
  framer2.feed(inav.data(), inav.size(), [&](const UbxFrame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), 6u);
  std::vector<std::uint8_t> payload = frames[1].payload;
  payload[8 + 5] ^= 0x10;
  const auto corrupt = encodeUbxFrame(0x02, 0x13, payload);
  UbxDecoder decoder;
  decoder.feed(corrupt.data(), corrupt.size(), {});
  EXPECT_EQ(decoder.counters().count(StreamProblemKind::ChecksumError), 1u);
  EXPECT_NE(decoder.counters().problems.at(0).describe().find("CRC-24Q"), std::string::npos);
}

TEST(UbxGeneratedSeeds, FuzzEntryOverTheCorpus) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(PPP_FUZZ_DIR) + "/corpus/ubx")) {
    const std::string bytes = test::readFileBytes(e.path().string());
    EXPECT_NO_THROW(fuzz::fuzzUbx(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) << e.path();
    ++n;
  }
  EXPECT_GE(n, 5u);
}

}  // namespace
}  // namespace ppp
