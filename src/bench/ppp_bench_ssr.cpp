// ppp_bench_ssr: decode throughput of the RTCM SSR decoder (framer + decoder)
// on a generated 1-h SSR stream at 5 s, the way a real-time service sends it:
// per epoch combined orbit+clock for GPS (31), GLONASS (22), Galileo (24) and
// BeiDou (30) satellites, code biases (4 signals) and phase biases (3 signals)
// per satellite, written by the encoder. Prints MB/s, messages/s and the real-
// time factor; asserts nothing.
//
//   ppp_bench_ssr [repeats=20]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"

namespace {

using Clock = std::chrono::steady_clock;
using namespace ppp;

std::vector<std::uint8_t> generateHour(std::size_t* messages) {
  const std::vector<std::pair<GnssSystem, int>> systems = {
      {GnssSystem::GPS, 31}, {GnssSystem::GLONASS, 22}, {GnssSystem::Galileo, 24}, {GnssSystem::BeiDou, 30}};
  std::vector<std::uint8_t> bytes;
  *messages = 0;
  const GnssTime start = GnssTime::fromGpsWeek(2420, 100000.0);
  for (int e = 0; e < 720; ++e) {
    const GnssTime t = start + 5.0 * e;
    for (const auto& [sys, n] : systems) {
      SsrMessage m;
      m.header.system = sys;
      m.header.update_interval_code = 2;
      double sow = t.gpsWeek().seconds_of_week;  // the SSR epoch time in the system's own time scale
      if (sys == GnssSystem::GLONASS) sow = glonassSecondsOfDay(t);
      if (sys == GnssSystem::BeiDou) sow = toBdtWeek(t).seconds_of_week;
      m.header.epoch_time_s = static_cast<std::uint32_t>(sow);
      SsrMessage orbit = m, code = m, phase = m;
      orbit.header.kind = SsrMessageKind::Combined;
      orbit.header.datum_regional = false;
      code.header.kind = SsrMessageKind::CodeBias;
      phase.header.kind = SsrMessageKind::PhaseBias;
      for (int prn = 1; prn <= n; ++prn) {
        const SatelliteId s{sys, prn};
        const double phase_angle = 0.01 * e + prn;
        SsrOrbitCorrection o;
        o.satellite = s;
        o.iod = prn % 200;
        o.radial_m = 0.3 * std::sin(phase_angle);
        o.along_m = 0.8 * std::cos(phase_angle);
        o.cross_m = -0.4 * std::sin(2 * phase_angle);
        o.radial_dot_mps = 1e-4 * std::cos(phase_angle);
        SsrClockCorrection c;
        c.satellite = s;
        c.c0_m = 1.5 * std::sin(0.7 * phase_angle);
        c.c1_m_per_s = 2e-4;
        orbit.orbits.push_back(o);
        orbit.clocks.push_back(c);
        SsrCodeBias cb;
        cb.satellite = s;
        for (int id : {0, 2, 5, 8}) cb.biases.push_back({id, ssrSignalCode(sys, id, false), 0.01 * (id + prn)});
        code.code_biases.push_back(cb);
        SsrPhaseBias pb;
        pb.satellite = s;
        pb.yaw_rad = 1.0;
        for (int id : {0, 2, 5}) pb.biases.push_back({id, ssrSignalCode(sys, id, false), true, 2, 1, 0.001 * id});
        phase.phase_biases.push_back(pb);
      }
      for (SsrMessage* msg : {&orbit, &code, &phase}) {
        // Split into messages of at most 16 satellites (frames stay below 1023 bytes).
        const std::size_t total = msg->header.kind == SsrMessageKind::Combined ? msg->orbits.size()
                                  : msg->header.kind == SsrMessageKind::CodeBias ? msg->code_biases.size()
                                                                                 : msg->phase_biases.size();
        for (std::size_t i = 0; i < total; i += 16) {
          const std::size_t end = std::min(total, i + 16);
          SsrMessage part = *msg;
          part.orbits.clear(); part.clocks.clear(); part.code_biases.clear(); part.phase_biases.clear();
          for (std::size_t k = i; k < end; ++k) {
            if (!msg->orbits.empty()) { part.orbits.push_back(msg->orbits[k]); part.clocks.push_back(msg->clocks[k]); }
            if (!msg->code_biases.empty()) part.code_biases.push_back(msg->code_biases[k]);
            if (!msg->phase_biases.empty()) part.phase_biases.push_back(msg->phase_biases[k]);
          }
          part.header.multiple_message = end < total;
          const auto frame = encodeSsrFrame(part);
          bytes.insert(bytes.end(), frame.begin(), frame.end());
          ++*messages;
        }
      }
    }
  }
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  std::size_t messages = 0;
  const auto g0 = Clock::now();
  const std::vector<std::uint8_t> stream = generateHour(&messages);
  const double gen_s = std::chrono::duration<double>(Clock::now() - g0).count();
  std::printf("generated 1 h of SSR at 5 s: %zu messages, %.2f MB (encoded in %.3f s)\n", messages,
              stream.size() / 1e6, gen_s);
  const GnssTime reference = GnssTime::fromGpsWeek(2420, 100000.0);
  std::size_t decoded = 0, values = 0;
  const auto t0 = Clock::now();
  for (int r = 0; r < repeats; ++r) {
    Rtcm3Framer framer;
    RtcmSsrDecoder decoder(reference);
    constexpr std::size_t kChunk = 1024;  // as from a socket
    for (std::size_t i = 0; i < stream.size(); i += kChunk)
      framer.feed(stream.data() + i, std::min(kChunk, stream.size() - i), [&](const Rtcm3Frame& f) { decoder.decode(f); });
    framer.finish();
    for (const auto& m : decoder.takeMessages()) {
      ++decoded;
      values += m.orbits.size() + m.code_biases.size() + m.phase_biases.size();
    }
  }
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  const double mb = stream.size() * static_cast<double>(repeats) / 1e6;
  std::printf("decoded %d x: %.1f MB/s, %.0f messages/s, %.0f satellite blocks/s, %.0f x real time (1 h in %.2f ms)\n",
              repeats, mb / s, decoded / s, values / s, 3600.0 * repeats / s, 1e3 * s / repeats);
  return decoded == messages * static_cast<std::size_t>(repeats) ? 0 : 1;
}
