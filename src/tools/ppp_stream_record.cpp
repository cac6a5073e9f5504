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

// The command line: the spec, the output file, the duration [s] and the format.
struct RecordArguments {
  std::string spec_text, out_path, format_text;
  std::optional<double> duration_s;
};

// What a recording counted: bytes, the format found, its framers, and whether it ended on a permanent error.
struct Recording {
  ppp::StreamFormat format = ppp::StreamFormat::Unknown;
  ppp::Rtcm3Framer rtcm;
  ppp::UbxFramer ubx;
  std::vector<std::uint8_t> undetected;  // bytes before the format is known
  std::uint64_t bytes = 0;
  bool permanent_error = false;
};

// Step 1: the arguments read; an exit code (2) on a usage error.
std::optional<int> parseArguments(int argc, char** argv, RecordArguments& args) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) args.out_path = argv[++i];
    else if (a == "--duration" && i + 1 < argc) {
      char* end = nullptr;
      args.duration_s = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(*args.duration_s > 0.0)) {
        std::fprintf(stderr, "ppp_stream_record: --duration '%s' is not a positive number of seconds\n", argv[i]);
        return 2;
      }
    } else if (a == "--format" && i + 1 < argc) args.format_text = argv[++i];
    else if (!a.empty() && a[0] != '-' && args.spec_text.empty()) args.spec_text = a;
    else return usage();
  }
  if (args.spec_text.empty() || args.out_path.empty()) return usage();
  if (!args.format_text.empty() && args.format_text != "rtcm3" && args.format_text != "ubx") {
    std::fprintf(stderr, "ppp_stream_record: --format '%s': expected rtcm3 or ubx\n", args.format_text.c_str());
    return 2;
  }
  return std::nullopt;
}

// Step 2: the spec parsed and its NTRIP credentials resolved; an exit code (2) on a bad spec.
std::optional<int> parseSpec(const RecordArguments& args, ppp::ByteSourceSpec& spec) {
  try {
    spec = ppp::parseByteSourceSpec(args.spec_text);
    ppp::resolveNtripCredentials(spec, std::getenv(ppp::kNtripCredentialsEnvironment));
  } catch (const ppp::ByteSourceSpecError& e) {
    std::fprintf(stderr, "ppp_stream_record: %s\n", e.what());
    return 2;
  }
  return std::nullopt;
}

// The format of --format, else of the spec's format=, else unknown (detected from the bytes).
ppp::StreamFormat requestedFormat(std::string format_text, const ppp::ByteSourceSpec& spec) {
  if (format_text.empty() && spec.format) format_text = *spec.format;
  return format_text.empty() ? ppp::StreamFormat::Unknown
         : format_text == "ubx" ? ppp::StreamFormat::Ubx
                                : ppp::StreamFormat::Rtcm3;
}

// Bytes given to the framer of the recording's format.
void feedFramer(Recording& rec, const std::uint8_t* data, std::size_t size) {
  if (rec.format == ppp::StreamFormat::Rtcm3) rec.rtcm.feed(data, size, [](const ppp::Rtcm3Frame&) {});
  if (rec.format == ppp::StreamFormat::Ubx) rec.ubx.feed(data, size, [](const ppp::UbxFrame&) {});
}

// Bytes read written to the file and framed; before the format is known they are kept until it is detected.
void recordBytes(Recording& rec, std::ofstream& out, const std::vector<std::uint8_t>& buffer, std::size_t size) {
  out.write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(size));
  rec.bytes += size;
  if (rec.format == ppp::StreamFormat::Unknown) {
    rec.undetected.insert(rec.undetected.end(), buffer.begin(), buffer.begin() + static_cast<long>(size));
    rec.format = ppp::detectStreamFormat(rec.undetected.data(), rec.undetected.size());
    if (rec.format != ppp::StreamFormat::Unknown) {
      feedFramer(rec, rec.undetected.data(), rec.undetected.size());
      rec.undetected.clear();
    }
  } else {
    feedFramer(rec, buffer.data(), size);
  }
}

// Step 3: reads until the duration [s], the end of a replay, a signal or a permanent error.
void recordUntilStop(ppp::ByteSource& source, std::ofstream& out, std::optional<double> duration_s,
                     std::chrono::steady_clock::time_point start, Recording& rec) {
  std::vector<std::uint8_t> buffer(65536);
  while (!g_stop) {
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (duration_s && elapsed_s >= *duration_s) break;
    auto wait = std::chrono::milliseconds(200);
    if (duration_s) {
      wait = std::min(wait, std::chrono::milliseconds(static_cast<long long>((*duration_s - elapsed_s) * 1000.0) + 1));
    }
    const ppp::ByteSourceRead got = source.read(buffer.data(), buffer.size(), wait);
    if (got.status == ppp::ByteSourceStatus::Closed) break;
    if (got.status == ppp::ByteSourceStatus::Error) {
      std::fprintf(stderr, "ppp_stream_record: %s\n", got.error->describe().c_str());
      if (ppp::isPermanentByteSourceError(got.error->kind)) {
        rec.permanent_error = true;
        break;
      }
      continue;
    }
    if (got.status != ppp::ByteSourceStatus::Data) continue;
    recordBytes(rec, out, buffer, got.size);
  }
}

// Step 4a: frames per type, checksum errors, garbage, NMEA and truncated frames of the format found.
void printFramerCounters(const Recording& rec) {
  const ppp::StreamCounters& f = rec.format == ppp::StreamFormat::Ubx ? rec.ubx.counters() : rec.rtcm.counters();
  if (rec.format == ppp::StreamFormat::Unknown) return;
  std::printf("frames: %llu\n", static_cast<unsigned long long>(f.frames));
  for (const auto& [type, count] : f.frames_by_type) {
    if (rec.format == ppp::StreamFormat::Ubx) {
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

// Step 4b: connects, reconnects, stalls, GGA sent, errors by kind and the last error of the source.
void printSourceCounters(const ppp::ByteSourceCounters& c) {
  std::printf("connects: %llu, reconnects: %llu, stalls: %llu, GGA sent: %llu\n",
              static_cast<unsigned long long>(c.connects), static_cast<unsigned long long>(c.reconnects),
              static_cast<unsigned long long>(c.stalls), static_cast<unsigned long long>(c.gga_sent));
  for (const auto& [kind, count] : c.errors_by_kind) {
    std::printf("errors %s: %llu\n", std::string(ppp::byteSourceErrorKindName(kind)).c_str(),
                static_cast<unsigned long long>(count));
  }
  if (c.last_error) std::printf("last error: %s\n", c.last_error->describe().c_str());
}

}  // namespace

int main(int argc, char** argv) {
  RecordArguments args;
  if (const auto exit_code = parseArguments(argc, argv, args)) return *exit_code;  // 1. arguments
  ppp::ByteSourceSpec spec;
  if (const auto exit_code = parseSpec(args, spec)) return *exit_code;  // 2. spec and credentials
  Recording rec;
  rec.format = requestedFormat(args.format_text, spec);
  std::ofstream out(args.out_path, std::ios::binary | std::ios::trunc);
  if (!out) {
    std::fprintf(stderr, "ppp_stream_record: cannot write %s: %s\n", args.out_path.c_str(), std::strerror(errno));
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
  std::fprintf(stderr, "ppp_stream_record: recording %s to %s\n", source->describe().c_str(), args.out_path.c_str());
  const auto start = std::chrono::steady_clock::now();
  recordUntilStop(*source, out, args.duration_s, start, rec);  // 3. record
  out.flush();
  const bool write_failed = !out;
  out.close();
  rec.rtcm.finish();
  rec.ubx.finish();
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // 4. Diagnostics.
  std::printf("source: %s\n", source->describe().c_str());
  std::printf("recorded: %llu bytes in %.1f s to %s\n", static_cast<unsigned long long>(rec.bytes), elapsed_s,
              args.out_path.c_str());
  std::printf("format: %s\n", std::string(ppp::streamFormatName(rec.format)).c_str());
  printFramerCounters(rec);
  printSourceCounters(source->counters());
  if (write_failed) {
    std::fprintf(stderr, "ppp_stream_record: writing %s failed\n", args.out_path.c_str());
    return 1;
  }
  return rec.permanent_error || rec.bytes == 0 ? 1 : 0;
}
