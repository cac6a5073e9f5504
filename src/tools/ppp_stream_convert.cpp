// ppp_stream_convert FILE --obs OUT.rnx [--nav OUT.nav] [--ref-date YYYY/MM/DD [HH:MM:SS]]
//
// RINEX 3.04 observation (and navigation) files from a receiver recording, as
// RTKLIB `convbin` does. The format is recognised by content: RTCM 3 (preamble
// 0xD3, CRC-24Q) or u-blox UBX (sync 0xB5 0x62). MSM epochs carry no week: give
// --ref-date (any day within half a week of the data, like convbin -tr) unless
// the stream holds Galileo or BeiDou ephemerides, which carry the full week.
// Stream problems are printed with their byte offset and frame index.
#include <cstdio>
#include <cstring>
#include <string>

#include "ppp_bayes_tree/app/stream_convert.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: ppp_stream_convert FILE --obs OUT.rnx [--nav OUT.nav] [--ref-date YYYY/MM/DD [HH:MM:SS]]\n"
               "  RTCM 3 (MSM4-7, 1005/1006/1007/1008/1033, 1019/1020/1042/1044/1045/1046) to RINEX 3.04.\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ppp;
  std::string input, obs_path, nav_path, ref_text;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--obs" && i + 1 < argc) obs_path = argv[++i];
    else if (a == "--nav" && i + 1 < argc) nav_path = argv[++i];
    else if (a == "--ref-date" && i + 1 < argc) {
      ref_text = argv[++i];
      if (i + 1 < argc && std::strchr(argv[i + 1], ':') && argv[i + 1][0] != '-') ref_text += std::string(" ") + argv[++i];
    } else if (a == "-h" || a == "--help") return usage();
    else if (!a.empty() && a[0] != '-' && input.empty()) input = a;
    else {
      std::fprintf(stderr, "ppp_stream_convert: unknown argument '%s'\n", a.c_str());
      return usage();
    }
  }
  if (input.empty() || obs_path.empty()) return usage();
  try {
    Rtcm3DecoderOptions options;
    if (!ref_text.empty()) {
      options.reference_time = parseReferenceDate(ref_text);
      if (!options.reference_time) {
        std::fprintf(stderr, "ppp_stream_convert: bad --ref-date '%s' (YYYY/MM/DD [HH:MM:SS])\n", ref_text.c_str());
        return 2;
      }
    }
    const StreamConversion result =
        convertStreamToRinex(input, obs_path, nav_path.empty() ? std::nullopt : std::optional<std::string>(nav_path),
                             options);
    const std::size_t epochs = result.epochs, records = result.navigation_records;
    const StreamCounters& c = result.counters;
    std::printf("%s: %llu bytes, %llu frames, %zu epochs written to %s", input.c_str(),
                static_cast<unsigned long long>(c.bytes), static_cast<unsigned long long>(c.frames), epochs,
                obs_path.c_str());
    if (!nav_path.empty()) std::printf(", %zu navigation records to %s", records, nav_path.c_str());
    std::printf("\n");
    std::fputs(c.problemLines().c_str(), stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppp_stream_convert: %s\n", e.what());
    return 1;
  }
}
