// ppp_bench_streams: RTCM 3 decode throughput on a generated stream.
//
// Builds 1 h of a 10 Hz multi-GNSS MSM7 stream in memory with the MSM7 encoder
// (io/rtcm/rtcm3_msm_encoder.h): GPS 10 satellites x 3 signals, GLONASS 8 x 2,
// Galileo 8 x 3, BeiDou 10 x 2, pseudoranges, phases and Dopplers varying
// epoch to epoch, then decodes it with Rtcm3Decoder in 64 KiB chunks on one core
// and prints MB/s, epochs/s and the factor over real time for a 10 Hz receiver
// (target: at least 100x). The SSR part of the benchmark is the SSR decoder's.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_msm_encoder.h"

int main(int argc, char** argv) {
  using namespace ppp;
  const double hours = argc > 1 ? std::atof(argv[1]) : 1.0;
  const int epochs = static_cast<int>(hours * 3600.0 * 10.0);
  struct SystemSpec {
    GnssSystem system;
    int satellites;
    const char* signals;
  };
  const SystemSpec specs[] = {{GnssSystem::GPS, 10, "1C2W5Q"},
                              {GnssSystem::GLONASS, 8, "1C2P"},
                              {GnssSystem::Galileo, 8, "1C5Q7Q"},
                              {GnssSystem::BeiDou, 10, "2I7I"}};
  MsmEncodeOptions options;
  for (int slot = 1; slot <= 8; ++slot) options.glonass_channels.set(slot, slot - 4);
  const GnssTime start = GnssTime::fromGpsWeek(2300, 200000.0);
  std::vector<std::uint8_t> stream;
  stream.reserve(static_cast<std::size_t>(epochs) * 1200);
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < epochs; ++k) {
    StreamEpoch e;
    e.time = start + 0.1 * k;
    for (const auto& spec : specs) {
      for (int s = 1; s <= spec.satellites; ++s) {
        StreamSatellite sat;
        sat.satellite = SatelliteId{spec.system, s};
        const double range = 20.0e6 + 1.0e5 * s + 700.0 * 0.1 * k * std::sin(s);
        for (int j = 0; spec.signals[2 * j]; ++j) {
          StreamSignal g;
          g.band = spec.signals[2 * j];
          g.attribute = spec.signals[2 * j + 1];
          g.pseudorange_m = range + 0.3 * j + 0.01 * (k % 7);
          g.carrier_phase_cycles = (range + 0.05 * j) / 0.2;
          g.doppler_hz = -700.0 * std::sin(s) / 0.2;
          g.cnr_dbhz = 40.0 + s * 0.5;
          g.lock_time_s = 0.1 * k;
          sat.signals.push_back(g);
        }
        e.satellites.push_back(sat);
      }
    }
    for (std::size_t i = 0; i < 4; ++i) {
      options.more_messages_follow = i < 3;
      for (const auto& p : encodeMsm7(e, specs[i].system, options)) {
        const auto f = encodeRtcm3Frame(p);
        stream.insert(stream.end(), f.begin(), f.end());
      }
    }
  }
  const auto t1 = std::chrono::steady_clock::now();
  Rtcm3DecoderOptions decode_options;
  decode_options.reference_time = start;
  decode_options.glonass_channels = options.glonass_channels;
  Rtcm3Decoder decoder(decode_options);
  std::size_t decoded = 0, signals = 0;
  const std::size_t chunk = 1 << 16;
  for (std::size_t i = 0; i < stream.size(); i += chunk) {
    decoder.feed(stream.data() + i, std::min(chunk, stream.size() - i));
    auto& out = decoder.output();
    decoded += out.epochs.size();
    for (const auto& e : out.epochs)
      for (const auto& s : e.satellites) signals += s.signals.size();
    out.clear();
  }
  decoder.finish();
  decoded += decoder.output().epochs.size();
  const auto t2 = std::chrono::steady_clock::now();
  const double encode_s = std::chrono::duration<double>(t1 - t0).count();
  const double decode_s = std::chrono::duration<double>(t2 - t1).count();
  const double mb = stream.size() / 1e6;
  std::printf("generated %.2f h of 10 Hz MSM7 (GPS/GLONASS/Galileo/BeiDou, 36 satellites, 90 signals): %d epochs, "
              "%.1f MB, encoded in %.2f s\n",
              hours, epochs, mb, encode_s);
  std::printf("decode: %.3f s, %.1f MB/s, %.0f epochs/s, %zu epochs, %zu signals, %llu problems\n", decode_s,
              mb / decode_s, decoded / decode_s, decoded, signals,
              static_cast<unsigned long long>(decoder.counters().totalProblems()));
  std::printf("real-time factor for a 10 Hz receiver: %.0fx (target >= 100x)\n", (epochs / 10.0) / decode_s);
  return decoded == static_cast<std::size_t>(epochs) ? 0 : 1;
}
