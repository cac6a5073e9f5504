// ppp_stream_inspect FILE [--json] [--ref-date YYYY/MM/DD [HH:MM:SS]]
//
// Tells what a receiver or correction recording holds: frames per message type,
// epochs, span, rate and gaps, CRC errors and other problems (byte offset and
// frame index), satellites and signals per system, ephemerides, the station
// (app/stream_inspection.h). --json prints the same as one JSON object.
// MSM epochs carry no week: without --ref-date they are placed only when the
// stream has a Galileo or BeiDou ephemeris. Exit: 0, 1 on error, 2 usage.
#include <cstdio>
#include <cstring>
#include <string>

#include "ppp_bayes_tree/app/stream_inspection.h"

int main(int argc, char** argv) {
  std::string path, ref;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json") json = true;
    else if (a == "--ref-date" && i + 1 < argc) {
      ref = argv[++i];
      if (i + 1 < argc && std::strchr(argv[i + 1], ':') && argv[i + 1][0] != '-') ref += std::string(" ") + argv[++i];
    } else if (!a.empty() && a[0] != '-' && path.empty()) path = a;
    else {
      std::fprintf(stderr, "usage: ppp_stream_inspect FILE [--json] [--ref-date YYYY/MM/DD [HH:MM:SS]]\n");
      return 2;
    }
  }
  if (path.empty()) {
    std::fprintf(stderr, "usage: ppp_stream_inspect FILE [--json] [--ref-date YYYY/MM/DD [HH:MM:SS]]\n");
    return 2;
  }
  try {
    ppp::Rtcm3DecoderOptions options;
    if (!ref.empty() && !(options.reference_time = ppp::parseReferenceDate(ref))) {
      std::fprintf(stderr, "ppp_stream_inspect: bad --ref-date '%s'\n", ref.c_str());
      return 2;
    }
    const ppp::StreamInspection s = ppp::inspectStreamFile(path, options);
    std::fputs((json ? ppp::streamInspectionJson(s) : ppp::formatStreamInspection(s)).c_str(), stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppp_stream_inspect: %s\n", e.what());
    return 1;
  }
}
