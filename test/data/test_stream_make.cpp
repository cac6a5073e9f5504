// CasterStreamBuilder (app/caster_stream_builder.h, ppp_stream_make's core): the
// ESBC 2020-177 window 00:00-00:45 made into one caster stream (1006/1033,
// MSM7 of every system, the broadcast file's records from their transmission
// time with 60-s repeats, SSR frames), then:
//  a) the stream carries the RINEX observations to their printed precision:
//     every value MSM7 can carry, decoded and rounded to the RINEX digits, is
//     the RINEX value;
//  b) ppp_solve's pipeline with the stream's navigation records (and SSR) and
//     the RINEX observations equals the RINEX navigation run to 1 mm: the
//     records are sent before they serve, and SSR picks them by IOD;
//  c) the stream's observations converted to RINEX (ppp_stream_convert's path:
//     MSM7 values at RINEX precision) give the RINEX run to 1 mm;
//  d) `ppp_solve --rtcm MADE --nav MADE --ssr SSR` (full MSM7 resolution:
//     pseudorange 2^-29 ms = 0.56 mm and phase 2^-31 ms = 0.14 mm steps instead
//     of RINEX's 1 mm / 0.001 cycle) differs from the RINEX run by that
//     quantisation only: the float solution of the first minutes (3D sigma
//     metres) amplifies sub-millimetre phase differences into millimetres
//     (measured: 11 mm at 00:02 with sigma 2.5 m, 1.4 mm after 30 min); the test
//     bounds each epoch's difference by 2 % of its formal 3D sigma, and by 2 mm
//     after the first 30 min;
//  e) the stream's records: each sent first at its transmission time, repeats
//     at 60 s, records transmitted before the window ahead of the first epoch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

#include "ppp_bayes_tree/app/stream_convert.h"
#include "ppp_bayes_tree/app/caster_stream_builder.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_writer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_ephemeris_encoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "esbc_stream_fixture.h"
#include "test_support.h"

namespace ppp {
namespace {

struct Made {
  GnssTime start, until;
  std::string dir, rinex_window, made, ssr, nav;
  std::vector<std::string> atx;
  std::vector<ObsEpoch> rinex_epochs;
  std::vector<TimedFrame> frames;
  std::size_t records_in_file = 0;
  std::size_t records_sent = 0;
};

const Made& made() {
  static const Made m = [] {
    Made m;
    m.start = test::gpst(2020, 6, 25, 0, 0, 0);
    m.until = test::gpst(2020, 6, 25, 0, 45, 0);
    m.dir = test::tempDir("stream_make").string();
    m.nav = test::esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx");
    m.atx = {test::dataPath("antex/igs20_gps_satellites_trim.atx"), test::dataPath("antex/igs05_esbc_receiver_trim.atx")};
    // The RINEX window (as read: the values round trip through the writer).
    RinexObservationSource source(test::esbcPath("ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz"));
    CasterStreamBuilder builder;  // the tool's defaults
    builder.setStation(source.header());
    m.rinex_window = m.dir + "/ESBC_window.rnx";
    {
      std::ofstream out(m.rinex_window);
      RinexObsWriter writer(out);
      writer.writeHeader(source.header());
      ObsEpoch epoch;
      while (source.next(epoch) == ObservationRead::Epoch && !(m.until < epoch.time)) {
        writer.writeEpoch(epoch, source.header());
        builder.addEpoch(epoch);
        m.rinex_epochs.push_back(epoch);
      }
    }
    const NavData nav = readRinexNav(m.nav);
    m.records_in_file = nav.recordCount();
    builder.addNavigation(nav);
    // SSR for the window (GPS, 5 s, centre of mass), as ppp_ssr_encode makes it.
    const std::vector<std::uint8_t> ssr_bytes = test::esbcGpsSsrStream(nav, m.start - 60.0, m.until + 60.0);
    m.ssr = m.dir + "/SSRC00TST_esbc.rtcm3";
    test::writeFileBytes(m.ssr, ssr_bytes);
    builder.addSsrStream(ssr_bytes);
    EXPECT_EQ(builder.counters().totalProblems(), 0u);
    const CasterStream stream = builder.build();
    m.frames = stream.frames;
    m.records_sent = stream.records_sent;
    m.made = m.dir + "/ESBC_made.rtcm3";
    writeFrames(m.made, m.frames);
    return m;
  }();
  return m;
}

struct Fix {
  std::optional<Eigen::Vector3d> position_ecef_m;
  double sigma_3d_m = 0.0;
};
using Fixes = std::map<GnssTime, Fix>;

Fixes run(const PppInputFiles& files, const std::string& estimator_name) {
  const PppConfig config = loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp_real_data.yaml");
  PppPipeline pipeline(files, config);
  std::string why;
  auto estimator = makeEstimator(estimator_name, config, &why);
  EXPECT_TRUE(estimator) << why;
  Fixes out;
  pipeline.run(*estimator, [&](const PppEpochRecord& rec) {
    if (rec.refused) return;
    Fix f;
    if (rec.status == EpochStatus::Ok) {
      f.position_ecef_m = rec.solution.position_ecef_m;
      if (rec.solution.covariance_ecef_m2) f.sigma_3d_m = std::sqrt(rec.solution.covariance_ecef_m2->trace());
    }
    out[rec.solution.time] = f;
  });
  return out;
}

PppInputFiles rinexFiles(const Made& m) {
  PppInputFiles f;
  f.obs = m.rinex_window;
  f.nav = {m.nav};
  f.ssr = m.ssr;
  f.atx = m.atx;
  return f;
}

struct Difference {
  std::size_t compared = 0, mismatched = 0;
  double max_m = 0.0, max_over_sigma = 0.0, max_after_30min_m = 0.0;
};
Difference compare(const Fixes& a, const Fixes& b, const GnssTime& start) {
  Difference d;
  for (const auto& [t, x] : a) {
    const auto it = b.find(t);
    if (it == b.end() || x.position_ecef_m.has_value() != it->second.position_ecef_m.has_value()) {
      ++d.mismatched;
      continue;
    }
    if (!x.position_ecef_m) continue;
    ++d.compared;
    const double e = (*x.position_ecef_m - *it->second.position_ecef_m).norm();
    d.max_m = std::max(d.max_m, e);
    d.max_over_sigma = std::max(d.max_over_sigma, e / it->second.sigma_3d_m);
    if (t - start >= 1800.0) d.max_after_30min_m = std::max(d.max_after_30min_m, e);
  }
  return d;
}

TEST(StreamMake, EsbcStreamCarriesTheRinexObservationsToTheirPrintedPrecision) {
  PPP_REQUIRE_SHARED_DATA();
  const Made& m = made();
  std::vector<std::uint8_t> bytes;
  for (const auto& f : m.frames) bytes.insert(bytes.end(), f.bytes.begin(), f.bytes.end());
  Rtcm3Decoder decoder;  // no reference date: the week comes from the Galileo records sent first
  decoder.setForeignFrameHandler([](const Rtcm3Frame& f) { return RtcmSsrDecoder::isSsrMessageType(f.message_type); });
  decoder.feed(bytes.data(), bytes.size());
  decoder.finish();
  EXPECT_EQ(decoder.counters().totalProblems(), 0u);
  const auto& epochs = decoder.output().epochs;
  ASSERT_EQ(epochs.size(), m.rinex_epochs.size());
  std::map<std::pair<SatelliteId, std::string>, GnssTime> arcs;
  std::size_t values = 0, unequal = 0, not_carried = 0;
  auto same = [](const std::optional<double>& a, const std::optional<double>& b) {
    return a.has_value() == b.has_value() && (!a || std::llround(*a * 1000.0) == std::llround(*b * 1000.0));
  };
  for (std::size_t i = 0; i < epochs.size(); ++i) {
    const StreamEpoch want = streamEpochFromRinex(m.rinex_epochs[i], arcs);
    const StreamEpoch& got = epochs[i];
    ASSERT_EQ(got.time, want.time);
    for (const auto& ws : want.satellites) {
      const StreamSatellite* gs = nullptr;
      for (const auto& s : got.satellites)
        if (s.satellite == ws.satellite) gs = &s;
      for (const auto& wsig : ws.signals) {
        if (!msmSignalId(ws.satellite.system, wsig.band, wsig.attribute)) {
          ++not_carried;  // no MSM signal id (e.g. GLONASS L3)
          continue;
        }
        const StreamSignal* g = nullptr;
        if (gs)
          for (const auto& s : gs->signals)
            if (s.band == wsig.band && s.attribute == wsig.attribute) g = &s;
        values += 4;
        if (!g) {
          unequal += 4;
          ADD_FAILURE() << ws.satellite.toString() << " " << wsig.band << wsig.attribute << " missing at "
                        << want.time.toString();
          continue;
        }
        for (const auto& [a, b, what] : {std::make_tuple(wsig.pseudorange_m, g->pseudorange_m, "C"),
                                         std::make_tuple(wsig.carrier_phase_cycles, g->carrier_phase_cycles, "L"),
                                         std::make_tuple(wsig.doppler_hz, g->doppler_hz, "D"),
                                         std::make_tuple(wsig.cnr_dbhz, g->cnr_dbhz, "S")}) {
          if (!same(a, b)) {
            ++unequal;
            if (unequal < 10)
              ADD_FAILURE() << ws.satellite.toString() << " " << what << wsig.band << wsig.attribute << " at "
                            << want.time.toString() << ": RINEX " << a.value_or(NAN) << ", stream " << b.value_or(NAN);
          }
        }
      }
    }
  }
  std::printf("[ figures  ] %zu epochs, %zu values (C/L/D/S of every signal MSM carries): %zu differ from RINEX at "
              "its printed precision; %zu signals without an MSM id left out\n",
              epochs.size(), values, unequal, not_carried);
  EXPECT_GT(values, 50000u);
  EXPECT_EQ(unequal, 0u);
}

TEST(StreamMake, EsbcRecordsAreSentFromTheirTransmissionTimeAndRepeated) {
  PPP_REQUIRE_SHARED_DATA();
  const Made& m = made();
  const double first_s = m.start.toGpsSecondsDouble() + 0.5;
  std::map<std::vector<std::uint8_t>, std::vector<double>> sends;
  std::map<int, std::size_t> by_type;
  double last_preamble_s = -1e300, first_msm_s = 1e300;
  for (const auto& f : m.frames) {
    ++by_type[f.message_type];
    if (f.message_type == 1019 || f.message_type == 1045 || f.message_type == 1046) {
      sends[f.bytes].push_back(f.arrival_s);
      if (f.arrival_s < first_s) last_preamble_s = std::max(last_preamble_s, f.arrival_s);
    }
    if (f.message_type == 1077) first_msm_s = std::min(first_msm_s, f.arrival_s);
  }
  EXPECT_LT(last_preamble_s, first_msm_s);  // the cache ahead of the first epoch
  EXPECT_EQ(sends.size(), m.records_sent);
  std::size_t repeated = 0;
  for (const auto& [bytes, times] : sends) {
    for (std::size_t i = 1; i < times.size(); ++i) EXPECT_NEAR(times[i] - times[i - 1], 60.0, 1e-6);
    repeated += times.size() > 1 ? 1 : 0;
  }
  std::printf("[ figures  ] %zu of the file's %zu records sent in the 45-min window (%zu repeated every 60 s); frames: "
              "1006 %zu, 1033 %zu, 1019 %zu, 1045 %zu, 1046 %zu, MSM7 GPS %zu, SSR 1060 %zu\n",
              m.records_sent, m.records_in_file, repeated, by_type[1006], by_type[1033], by_type[1019], by_type[1045],
              by_type[1046], by_type[1077], by_type[1060]);
  EXPECT_GT(m.records_sent, 100u);
  EXPECT_GT(repeated, 20u);
  EXPECT_EQ(by_type[1006], 10u);  // every 300 s in 45 min, and ahead of the first epoch
  EXPECT_EQ(by_type[1033], 10u);
  // Each record's first send: at its transmission time, or ahead of the first epoch.
  const NavData nav = readRinexNav(m.nav);
  std::size_t checked = 0;
  for (const auto& e : nav.gps) {
    const auto frame = encodeRtcm3Frame(encodeEphemerisPayload(e));
    const auto it = sends.find(frame);
    if (it == sends.end() || !e.transmission_sow) continue;
    double tx_s = GnssTime::fromGpsWeek(e.orbit.toe.gpsWeek().week, *e.transmission_sow).toGpsSecondsDouble();
    if (tx_s - e.orbit.toe.toGpsSecondsDouble() > 302400.0) tx_s -= 604800.0;
    EXPECT_DOUBLE_EQ(it->second.front(), std::max(tx_s, first_s - 1.0)) << e.satellite.toString();
    ++checked;
  }
  EXPECT_GT(checked, 20u);
}

TEST(StreamMake, PppOnTheMadeStreamEqualsTheRinexRun) {
  PPP_REQUIRE_SHARED_DATA();
  const Made& m = made();
  // The stream's observations at RINEX precision (ppp_stream_convert's RINEX), for c).
  const std::string converted = m.dir + "/made.rnx";
  convertStreamToRinex(m.made, converted, std::nullopt, {});
  for (const std::string estimator : {"ekf", "smoother"}) {
    const Fixes rinex = run(rinexFiles(m), estimator);
    ASSERT_GT(rinex.size(), 85u);
    // b) The stream's records and SSR, the RINEX observations.
    PppInputFiles nav_from_stream = rinexFiles(m);
    nav_from_stream.nav = {m.made};
    const Difference b = compare(run(nav_from_stream, estimator), rinex, m.start);
    // c) The stream's observations at RINEX precision (ppp_stream_convert's RINEX).
    PppInputFiles obs_converted = rinexFiles(m);
    obs_converted.obs = converted;
    obs_converted.nav = {m.made};
    const Difference c = compare(run(obs_converted, estimator), rinex, m.start);
    // d) ppp_solve --rtcm MADE --nav MADE --ssr SSR.
    PppInputFiles all = rinexFiles(m);
    all.obs = m.made;
    all.obs_format = ObservationFormat::Rtcm3;
    all.nav = {m.made};
    const Difference d = compare(run(all, estimator), rinex, m.start);
    std::printf("[ figures  ] %s, against RINEX obs+nav+SSR: (b) stream records: %zu epochs, max %.4f mm; (c) stream "
                "obs at RINEX precision: max %.4f mm; (d) --rtcm/--nav MADE: %zu epochs, %zu mismatched, max %.2f mm "
                "(%.2f %% of the 3D sigma), after 30 min %.2f mm\n",
                estimator.c_str(), b.compared, b.max_m * 1e3, c.max_m * 1e3, d.compared, d.mismatched, d.max_m * 1e3,
                d.max_over_sigma * 100.0, d.max_after_30min_m * 1e3);
    EXPECT_EQ(b.mismatched, 0u) << estimator;
    EXPECT_GT(b.compared, 85u) << estimator;
    EXPECT_LE(b.max_m, 1e-3) << estimator;
    EXPECT_EQ(c.mismatched, 0u) << estimator;
    EXPECT_LE(c.max_m, 1e-3) << estimator;
    EXPECT_EQ(d.mismatched, 0u) << estimator;
    EXPECT_GT(d.compared, 85u) << estimator;
    EXPECT_LE(d.max_over_sigma, 0.02) << estimator;
    EXPECT_LE(d.max_after_30min_m, 2e-3) << estimator;
  }
}

}  // namespace
}  // namespace ppp
