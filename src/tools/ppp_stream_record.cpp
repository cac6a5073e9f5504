// ppp_stream_record SPEC --out FILE [--duration S] [--format rtcm3|ubx]
//
// Records a live input (serial, TCP, NTRIP, or a file replay; the spec syntax is
// in io/transport/byte_source_spec.h) to FILE byte for byte, like RTKLIB's str2str, and
// prints our diagnostics at the end: bytes, frames per message type found by
// the RTCM 3 or UBX framer, CRC errors, garbage and NMEA bytes, reconnects,
// stalls and errors by kind. The format is --format, the spec's format=, or
// detected from the first complete frame. Errors are printed as they happen
// (the password never is). Stops after --duration seconds, at the end of a
// replayed file, on SIGINT/SIGTERM, or on a permanent error (authentication
// refused, unknown mountpoint). Exit: 0, 1 on error (nothing recorded or a
// permanent error), 2 usage.
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/transport/byte_source_spec.h"
#include "ppp_bayes_tree/io/transport/ntrip_credentials.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"

namespace {

volatile std::sig_atomic_t g_stop = 0;  // set by SIGINT/SIGTERM only
void onSignal(int) { g_stop = 1; }

int usage() {
  std::fprintf(stderr,
               "usage: ppp_stream_record SPEC --out FILE [--duration S] [--format rtcm3|ubx]\n"
               "  SPEC: serial:///dev/ttyACM0?baud=115200 | tcp://host:port |\n"
               "        ntrip://user:password@host:port/MOUNT[?version=1|2&gga_period_s=10&lat=..&lon=..&h=..] |\n"
               "        file:///path/x.rtcm3?speed=1\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string spec_text, out_path, format_text;
  std::optional<double> duration_s;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    else if (a == "--duration" && i + 1 < argc) {
      char* end = nullptr;
      duration_s = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(*duration_s > 0.0)) {
        std::fprintf(stderr, "ppp_stream_record: --duration '%s' is not a positive number of seconds\n", argv[i]);
        return 2;
      }
    } else if (a == "--format" && i + 1 < argc) format_text = argv[++i];
    else if (!a.empty() && a[0] != '-' && spec_text.empty()) spec_text = a;
    else return usage();
  }
  if (spec_text.empty() || out_path.empty()) return usage();
  if (!format_text.empty() && format_text != "rtcm3" && format_text != "ubx") {
    std::fprintf(stderr, "ppp_stream_record: --format '%s': expected rtcm3 or ubx\n", format_text.c_str());
    return 2;
  }
  ppp::ByteSourceSpec spec;
  try {
    spec = ppp::parseByteSourceSpec(spec_text);
    ppp::resolveNtripCredentials(spec, std::getenv(ppp::kNtripCredentialsEnvironment));
  } catch (const ppp::ByteSourceSpecError& e) {
    std::fprintf(stderr, "ppp_stream_record: %s\n", e.what());
    return 2;
  }
  if (format_text.empty() && spec.format) format_text = *spec.format;
  ppp::StreamFormat format = format_text.empty() ? ppp::StreamFormat::Unknown
                             : format_text == "ubx" ? ppp::StreamFormat::Ubx
                                                    : ppp::StreamFormat::Rtcm3;
  std::ofstream out(out_path, std::ios::binary | std::ios::trunc);
  if (!out) {
    std::fprintf(stderr, "ppp_stream_record: cannot write %s: %s\n", out_path.c_str(), std::strerror(errno));
    return 1;
  }
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);

  std::unique_ptr<ppp::ByteSource> source;
  try {
    source = ppp::openByteSource(spec);  // refuses e.g. a directory given as file://
  } catch (const ppp::ByteSourceSpecError& e) {
    std::fprintf(stderr, "ppp_stream_record: %s\n", e.what());
    return 2;
  }
  std::fprintf(stderr, "ppp_stream_record: recording %s to %s\n", source->describe().c_str(), out_path.c_str());
  ppp::Rtcm3Framer rtcm;
  ppp::UbxFramer ubx;
  std::vector<std::uint8_t> undetected;  // bytes before the format is known
  const auto feed = [&](const std::uint8_t* data, std::size_t size) {
    if (format == ppp::StreamFormat::Rtcm3) rtcm.feed(data, size, [](const ppp::Rtcm3Frame&) {});
    if (format == ppp::StreamFormat::Ubx) ubx.feed(data, size, [](const ppp::UbxFrame&) {});
  };
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t bytes = 0;
  bool permanent_error = false;
  std::vector<std::uint8_t> buffer(65536);
  while (!g_stop) {
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (duration_s && elapsed_s >= *duration_s) break;
    auto wait = std::chrono::milliseconds(200);
    if (duration_s) {
      wait = std::min(wait, std::chrono::milliseconds(static_cast<long long>((*duration_s - elapsed_s) * 1000.0) + 1));
    }
    const ppp::ByteSourceRead got = source->read(buffer.data(), buffer.size(), wait);
    if (got.status == ppp::ByteSourceStatus::Closed) break;
    if (got.status == ppp::ByteSourceStatus::Error) {
      std::fprintf(stderr, "ppp_stream_record: %s\n", got.error->describe().c_str());
      if (ppp::isPermanentByteSourceError(got.error->kind)) {
        permanent_error = true;
        break;
      }
      continue;
    }
    if (got.status != ppp::ByteSourceStatus::Data) continue;
    out.write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(got.size));
    bytes += got.size;
    if (format == ppp::StreamFormat::Unknown) {
      undetected.insert(undetected.end(), buffer.begin(), buffer.begin() + static_cast<long>(got.size));
      format = ppp::detectStreamFormat(undetected.data(), undetected.size());
      if (format != ppp::StreamFormat::Unknown) {
        feed(undetected.data(), undetected.size());
        undetected.clear();
      }
    } else {
      feed(buffer.data(), got.size);
    }
  }
  out.flush();
  const bool write_failed = !out;
  out.close();
  rtcm.finish();
  ubx.finish();
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const ppp::ByteSourceCounters& c = source->counters();
  std::printf("source: %s\n", source->describe().c_str());
  std::printf("recorded: %llu bytes in %.1f s to %s\n", static_cast<unsigned long long>(bytes), elapsed_s,
              out_path.c_str());
  std::printf("format: %s\n", std::string(ppp::streamFormatName(format)).c_str());
  const ppp::StreamCounters& f = format == ppp::StreamFormat::Ubx ? ubx.counters() : rtcm.counters();
  if (format != ppp::StreamFormat::Unknown) {
    std::printf("frames: %llu\n", static_cast<unsigned long long>(f.frames));
    for (const auto& [type, count] : f.frames_by_type) {
      if (format == ppp::StreamFormat::Ubx) {
        std::printf("  UBX 0x%02X 0x%02X: %llu\n", type >> 8, type & 0xFF, static_cast<unsigned long long>(count));
      } else {
        std::printf("  RTCM %d: %llu\n", type, static_cast<unsigned long long>(count));
      }
    }
    std::printf("checksum errors: %llu\n", static_cast<unsigned long long>(f.count(ppp::StreamProblemKind::ChecksumError)));
    std::printf("garbage bytes: %llu, NMEA bytes: %llu, truncated frames: %llu\n",
                static_cast<unsigned long long>(f.garbage_bytes), static_cast<unsigned long long>(f.nmea_bytes),
                static_cast<unsigned long long>(f.count(ppp::StreamProblemKind::TruncatedFrame)));
  }
  std::printf("connects: %llu, reconnects: %llu, stalls: %llu, GGA sent: %llu\n",
              static_cast<unsigned long long>(c.connects), static_cast<unsigned long long>(c.reconnects),
              static_cast<unsigned long long>(c.stalls), static_cast<unsigned long long>(c.gga_sent));
  for (const auto& [kind, count] : c.errors_by_kind) {
    std::printf("errors %s: %llu\n", std::string(ppp::byteSourceErrorKindName(kind)).c_str(),
                static_cast<unsigned long long>(count));
  }
  if (c.last_error) std::printf("last error: %s\n", c.last_error->describe().c_str());
  if (write_failed) {
    std::fprintf(stderr, "ppp_stream_record: writing %s failed\n", out_path.c_str());
    return 1;
  }
  return permanent_error || bytes == 0 ? 1 : 0;
}
