// ppp_stream_make --obs RINEX_OBS --nav NAV [--nav NAV ...] [--ssr SSR_STREAM]
//                 [--start "YYYY/MM/DD HH:MM:SS" --duration S] [--latency-s L]
//                 [--ssr-latency-s L] [--ephemeris-repeat-s R] [--systems GRECJS] --out FILE
//
// One RTCM 3 stream as a caster would send it for a processed day
// (app/caster_stream_builder.h): station 1006/1033 from the RINEX header, MSM7
// per epoch, each broadcast record (1019/1044, 1020, 1045/1046) from its
// transmission time and repeated, the SSR frames of --ssr (e.g. ppp_ssr_encode's)
// interleaved at their epochs. Replay it as if live: ppp_stream_record
// 'file:///PATH?speed=1', str2str -in file://PATH::T, or the nodes' live input.
// ppp_solve --rtcm FILE --nav FILE [--ssr FILE] processes it.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/app/caster_stream_builder.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex/observation_source.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"

namespace {

int usage(const char* why = nullptr) {
  if (why) std::fprintf(stderr, "ppp_stream_make: %s\n", why);
  std::fprintf(stderr,
               "usage: ppp_stream_make --obs RINEX_OBS --nav NAV [--nav NAV ...] [--ssr SSR_STREAM]\n"
               "                       [--start \"YYYY/MM/DD HH:MM:SS\" --duration S] [--latency-s 0.5]\n"
               "                       [--ssr-latency-s 2] [--ephemeris-repeat-s 60] [--systems GRECJS] --out FILE\n"
               "  One RTCM 3 stream as a caster sends it: 1006/1033 station, MSM7 epochs (arriving\n"
               "  --latency-s after their epoch), broadcast records 1019/1044/1020/1045/1046 from their\n"
               "  transmission time and repeated, SSR frames at their epoch + --ssr-latency-s.\n"
               "  Replay: ppp_stream_record 'file:///FILE?speed=1' ..., or ppp_solve --rtcm FILE --nav FILE.\n");
  return 2;
}

std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ppp::FileOpenError("cannot open " + path);
  return std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ppp;
  std::string obs_path, ssr_path, out_path, start_text;
  std::vector<std::string> nav_paths;
  std::optional<double> duration_s;
  CasterStreamOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& v) {
      if (i + 1 >= argc) return false;
      v = argv[++i];
      return true;
    };
    auto number = [&](double& x) {
      std::string v;
      if (!value(v)) return false;
      try {
        std::size_t used = 0;
        x = std::stod(v, &used);
        return used == v.size() && std::isfinite(x) && x >= 0.0;
      } catch (...) {
        return false;
      }
    };
    std::string v;
    double x = 0.0;
    if (a == "-h" || a == "--help") return usage();
    if (a == "--obs") {
      if (!value(obs_path)) return usage("--obs needs a RINEX observation file");
    } else if (a == "--nav") {
      if (!value(v)) return usage("--nav needs a RINEX navigation file");
      nav_paths.push_back(v);
    } else if (a == "--ssr") {
      if (!value(ssr_path)) return usage("--ssr needs an RTCM SSR stream file");
    } else if (a == "--out") {
      if (!value(out_path)) return usage("--out needs a file");
    } else if (a == "--start") {
      if (!value(start_text)) return usage("--start needs \"YYYY/MM/DD HH:MM:SS\"");
      if (i + 1 < argc && std::strchr(argv[i + 1], ':') && argv[i + 1][0] != '-') start_text += std::string(" ") + argv[++i];
    } else if (a == "--duration") {
      if (!number(x)) return usage("--duration needs seconds >= 0");
      duration_s = x;
    } else if (a == "--latency-s") {
      if (!number(options.observation_latency_s)) return usage("--latency-s needs seconds >= 0");
    } else if (a == "--ssr-latency-s") {
      if (!number(options.ssr_latency_s)) return usage("--ssr-latency-s needs seconds >= 0");
    } else if (a == "--ephemeris-repeat-s") {
      if (!number(options.ephemeris_repeat_s)) return usage("--ephemeris-repeat-s needs seconds >= 0 (0: no repeats)");
    } else if (a == "--systems") {
      if (!value(v)) return usage("--systems needs letters, e.g. GRE");
      for (char c : v) {
        const auto s = systemFromLetter(c);
        if (!s) return usage("--systems: unknown system letter");
        options.systems.insert(*s);
      }
    } else {
      std::fprintf(stderr, "ppp_stream_make: unknown argument '%s'\n", a.c_str());
      return usage();
    }
  }
  if (obs_path.empty() || out_path.empty()) return usage("--obs and --out are required");
  std::optional<GnssTime> start;
  if (!start_text.empty() && !(start = parseReferenceDate(start_text)))
    return usage("bad --start (YYYY/MM/DD [HH:MM:SS])");
  try {
    CasterStreamBuilder builder(options);
    RinexObservationSource source(obs_path);
    builder.setStation(source.header());
    if (!source.header().approx_position_ecef_m)
      std::fprintf(stderr, "ppp_stream_make: %s has no APPROX POSITION XYZ: no 1006 station message\n", obs_path.c_str());
    ObsEpoch epoch;
    ObservationRead r;
    while ((r = source.next(epoch)) == ObservationRead::Epoch) {
      if (start && epoch.time < *start) continue;
      if (start && duration_s && epoch.time - *start > *duration_s) break;
      if (!start && duration_s && builder.firstEpoch() && epoch.time - *builder.firstEpoch() > *duration_s) break;
      builder.addEpoch(epoch);
    }
    if (r == ObservationRead::Error && source.error())
      std::fprintf(stderr, "ppp_stream_make: %s line %zu: %s (epochs up to there are used)\n",
                   source.error()->file.c_str(), source.error()->line, source.error()->reason.c_str());
    if (builder.epochs() == 0) {
      std::fprintf(stderr, "ppp_stream_make: no observation epoch in %s%s\n", obs_path.c_str(),
                   start ? " in the window given" : "");
      return 1;
    }
    for (const auto& n : nav_paths) builder.addNavigation(readRinexNav(n));
    if (!ssr_path.empty()) builder.addSsrStream(readBytes(ssr_path));
    const CasterStream stream = builder.build();
    writeFrames(out_path, stream.frames);
    std::size_t bytes = 0;
    for (const auto& f : stream.frames) bytes += f.bytes.size();
    std::printf("%s: %zu frames, %zu bytes; %zu epochs %s .. %s, %zu broadcast records\n", out_path.c_str(),
                stream.frames.size(), bytes, builder.epochs(), builder.firstEpoch()->toString().c_str(),
                builder.lastEpoch()->toString().c_str(), stream.records_sent);
    std::string types;
    for (const auto& [type, n] : stream.frames_by_type) types += " " + std::to_string(type) + ":" + std::to_string(n);
    std::printf("frames per type:%s\n", types.c_str());
    const StreamCounters& c = builder.counters();
    std::fputs(c.problemLines().c_str(), stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppp_stream_make: %s\n", e.what());
    return 1;
  }
}
