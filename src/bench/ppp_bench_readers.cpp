// ppp_bench_readers: throughput of the RINEX observation reader on a large
// synthetic multi-GNSS file (plain, gzip and Compact RINEX), and peak RSS to
// show that reading streams. Prints figures, asserts nothing.
//
//   ppp_bench_readers [size_MB=200] [temp_dir]
//
// The synthetic data: 1 Hz epochs, 30 satellites (GPS, GLONASS, Galileo,
// BeiDou), 16 observation types each, smooth values with noise. The Compact
// RINEX copy is written by a small CRINEX 3.0 encoder below (3rd-order
// differences, as RNX2CRX does), and its restored text is compared with the
// plain file line by line.
#include <sys/resource.h>
#include <zlib.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/hatanaka_decoder.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

long peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024;
}

constexpr int kSats = 30;
constexpr int kTypes = 16;
const char* kCodes[kTypes] = {"C1C", "L1C", "D1C", "S1C", "C2W", "L2W", "D2W", "S2W",
                              "C5Q", "L5Q", "D5Q", "S5Q", "C7Q", "L7Q", "D7Q", "S7Q"};

std::string headerLine(const std::string& content, const char* label) {
  std::string s = content;
  s.resize(60, ' ');
  return s + label + "\n";
}

std::string rinexHeader() {
  std::string h = headerLine("     3.05           OBSERVATION DATA    M", "RINEX VERSION / TYPE");
  h += headerLine("ppp_bench_readers   ppp_bayes_tree      20260101 000000 UTC", "PGM / RUN BY / DATE");
  h += headerLine("BNCH", "MARKER NAME");
  h += headerLine("1                   SYNTH RECEIVER      1.0", "REC # / TYPE / VERS");
  h += headerLine("1                   TRM59800.00     NONE", "ANT # / TYPE");
  h += headerLine("  4331300.1600   567537.0810  4633133.5100", "APPROX POSITION XYZ");
  h += headerLine("        0.0000        0.0000        0.0000", "ANTENNA: DELTA H/E/N");
  for (char sys : {'G', 'R', 'E', 'C'}) {
    std::string a = std::string(1, sys) + "   16", b = "      ";
    for (int k = 0; k < kTypes; ++k) (k < 13 ? a : b) += std::string(" ") + kCodes[k];
    h += headerLine(a, "SYS / # / OBS TYPES") + headerLine(b, "SYS / # / OBS TYPES");
  }
  h += headerLine("     1.000", "INTERVAL");
  h += headerLine("  2026     5    13     0     0    0.0000000     GPS", "TIME OF FIRST OBS");
  h += headerLine("", "END OF HEADER");
  return h;
}

/// Writes the same synthetic epochs as plain RINEX 3.05 and as CRINEX 3.0.
class SyntheticWriter {
 public:
  SyntheticWriter() {
    const char letters[4] = {'G', 'R', 'E', 'C'};
    for (int s = 0; s < kSats; ++s) {
      char id[4];
      std::snprintf(id, sizeof(id), "%c%02d", letters[s % 4], s / 4 + 1);
      ids_.push_back(id);
      for (int k = 0; k < kTypes; ++k) {
        Series& x = series_[s][k];
        const int kind = k % 4;  // C L D S
        x.base = kind == 0 ? 20000000000LL + s * 100000000LL
               : kind == 1 ? 105000000000LL + s * 500000000LL
               : kind == 2 ? -3000000 - s * 200000
                           : 40000 + s * 300;
        x.rate = kind == 0 ? 700000 + s * 1000 : kind == 1 ? 3700000 + s * 5000 : kind == 2 ? 10 : 0;
      }
    }
  }

  /// Appends epoch `t` (seconds since 2026-05-13 00:00) to both texts.
  void epoch(long t, std::string& plain, std::string& crx) {
    char line[128];
    const int h = static_cast<int>(t / 3600 % 24), m = static_cast<int>(t / 60 % 60), sec = static_cast<int>(t % 60);
    const int day = 13 + static_cast<int>(t / 86400);
    std::snprintf(line, sizeof(line), "> 2026 05 %02d %02d %02d %02d.0000000  0 %2d", day, h, m, sec, kSats);
    plain += line;
    plain += '\n';
    std::string full = line;
    full += "      ";
    for (const auto& id : ids_) full += id;
    crx += first_ ? full : textDiff(prev_epoch_, full);
    crx += "\n\n";  // no receiver clock
    prev_epoch_ = full;
    for (int s = 0; s < kSats; ++s) {
      std::string rec = ids_[s];
      std::string cfields;
      std::string flags;
      for (int k = 0; k < kTypes; ++k) {
        Series& x = series_[s][k];
        noise_ = noise_ * 6364136223846793005ULL + 1442695040888963407ULL;
        const long long v = x.base + x.rate * t + static_cast<long long>((noise_ >> 33) % 2001) - 1000;
        char field[32];
        std::snprintf(field, sizeof(field), "%14.3f", static_cast<double>(v) / 1000.0);
        const char ssi = (k % 4 == 1) ? '7' : ' ';
        rec += field;
        rec += ' ';
        rec += ssi;
        flags += ' ';
        flags += ssi;
        if (k > 0) cfields += ' ';
        cfields += x.encode(v);
      }
      while (!rec.empty() && rec.back() == ' ') rec.pop_back();
      plain += rec;
      plain += '\n';
      if (first_) {
        while (!flags.empty() && flags.back() == ' ') flags.pop_back();
        cfields += ' ';
        cfields += flags;
      }
      crx += cfields;
      crx += '\n';
    }
    first_ = false;
  }

 private:
  struct Series {
    long long base = 0, rate = 0;
    long long d[4] = {};
    int count = 0;
    /// 3rd-order difference encoding ("3&v" at the start of the arc).
    std::string encode(long long v) {
      long long nd[4];
      nd[0] = v;
      const int k = count < 3 ? count : 3;
      for (int j = 1; j <= k; ++j) nd[j] = nd[j - 1] - d[j - 1];
      const std::string out = count == 0 ? "3&" + std::to_string(v) : std::to_string(nd[k]);
      for (int j = 0; j <= k; ++j) d[j] = nd[j];
      if (count < 3) ++count;
      return out;
    }
  };
  static std::string textDiff(const std::string& old_text, const std::string& new_text) {
    std::string d(std::max(old_text.size(), new_text.size()), ' ');
    for (std::size_t i = 0; i < d.size(); ++i) {
      const char o = i < old_text.size() ? old_text[i] : ' ';
      const char n = i < new_text.size() ? new_text[i] : ' ';
      d[i] = o == n ? ' ' : (n == ' ' ? '&' : n);
    }
    while (!d.empty() && d.back() == ' ') d.pop_back();
    return d;
  }

  std::vector<std::string> ids_;
  Series series_[kSats][kTypes];
  std::string prev_epoch_;
  bool first_ = true;
  unsigned long long noise_ = 12345;
};

struct ReadFigures {
  double seconds = 0;
  std::size_t epochs = 0, observations = 0, problems = 0;
};

ReadFigures readObservations(const std::string& path) {
  ReadFigures f;
  const auto t0 = Clock::now();
  ppp::RinexObsReader reader = ppp::RinexObsReader::open(path);
  ppp::ObsEpoch epoch;
  while (reader.next(epoch)) {
    ++f.epochs;
    f.observations += epoch.observations.size();
  }
  f.seconds = seconds(t0, Clock::now());
  f.problems = reader.report().problemCount();
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  const double target_mb = argc > 1 ? std::atof(argv[1]) : 200.0;
  const std::filesystem::path dir =
      argc > 2 ? std::filesystem::path(argv[2])
               : std::filesystem::temp_directory_path() / ("ppp_bench_readers_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string plain_path = (dir / "BNCH00XXX_R_20261330000_01D_01S_MO.rnx").string();
  const std::string gz_path = plain_path + ".gz";
  const std::string crx_path = (dir / "BNCH00XXX_R_20261330000_01D_01S_MO.crx").string();

  // 1. Generate.
  auto t0 = Clock::now();
  std::size_t plain_bytes = 0, crx_bytes = 0;
  long epochs = 0;
  {
    std::ofstream plain(plain_path, std::ios::binary), crx(crx_path, std::ios::binary);
    const std::string header = rinexHeader();
    plain << header;
    crx << headerLine("3.0                 COMPACT RINEX FORMAT", "CRINEX VERS   / TYPE")
        << headerLine("ppp_bench_readers                       01-Jan-26 00:00", "CRINEX PROG / DATE") << header;
    plain_bytes = header.size();
    SyntheticWriter writer;
    std::string p, c;
    while (plain_bytes < target_mb * 1e6) {
      p.clear();
      c.clear();
      for (int i = 0; i < 100; ++i) writer.epoch(epochs++, p, c);
      plain.write(p.data(), static_cast<std::streamsize>(p.size()));
      crx.write(c.data(), static_cast<std::streamsize>(c.size()));
      plain_bytes += p.size();
      crx_bytes += c.size();
    }
  }
  const double gen_s = seconds(t0, Clock::now());
  std::printf("generated %ld epochs x %d satellites x %d types: plain %.1f MB, CRX %.1f MB in %.1f s (%s)\n",
              epochs, kSats, kTypes, plain_bytes / 1e6, crx_bytes / 1e6, gen_s, dir.c_str());

  // 2. gzip copy (level 1, not timed as reading).
  t0 = Clock::now();
  {
    std::ifstream in(plain_path, std::ios::binary);
    gzFile out = gzopen(gz_path.c_str(), "wb1");
    std::vector<char> buf(1 << 20);
    while (in) {
      in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
      if (in.gcount() > 0) gzwrite(out, buf.data(), static_cast<unsigned>(in.gcount()));
    }
    gzclose(out);
  }
  const double gz_mb = std::filesystem::file_size(gz_path) / 1e6;
  std::printf("gzip -1 copy: %.1f MB in %.1f s\n", gz_mb, seconds(t0, Clock::now()));
  std::printf("peak RSS after generation: %ld MB\n\n", peakRssMb());

  // 3. Line reading baseline (LineSource only).
  t0 = Clock::now();
  {
    auto src = ppp::openLineSource(plain_path);
    std::string line;
    std::size_t n = 0;
    while (src->next(line)) ++n;
    const double s = seconds(t0, Clock::now());
    std::printf("LineSource only, plain:   %8.1f MB/s  (%zu lines)\n", plain_bytes / 1e6 / s, n);
  }

  // 4. Reader: plain, gzip, CRX.
  auto report = [&](const char* what, const ReadFigures& f, double mb, const char* unit) {
    std::printf("RinexObsReader, %-9s %8.1f MB/s %s  %9.0f epochs/s  %7.2f Mobs/s  (%zu epochs, %zu problems, %.2f s)\n",
                what, mb / f.seconds, unit, f.epochs / f.seconds, f.observations / f.seconds / 1e6, f.epochs,
                f.problems, f.seconds);
  };
  const ReadFigures plain = readObservations(plain_path);
  report("plain:", plain, plain_bytes / 1e6, "text      ");
  std::printf("peak RSS: %ld MB\n", peakRssMb());
  const ReadFigures gz = readObservations(gz_path);
  report("gzip:", gz, plain_bytes / 1e6, "text      ");
  std::printf("                           %8.1f MB/s compressed\n", gz_mb / gz.seconds);
  const ReadFigures crx = readObservations(crx_path);
  report("CRX:", crx, plain_bytes / 1e6, "restored  ");
  std::printf("                           %8.1f MB/s of .crx\n", crx_bytes / 1e6 / crx.seconds);

  // 5. CRX decoding alone, and equality with the plain text.
  t0 = Clock::now();
  {
    auto src = ppp::openObservationSource(crx_path);
    std::string line;
    std::size_t n = 0;
    while (src->next(line)) ++n;
    const double s = seconds(t0, Clock::now());
    std::printf("HatanakaDecoder alone:    %8.1f MB/s restored text, %.1f MB/s of .crx\n", plain_bytes / 1e6 / s,
                crx_bytes / 1e6 / s);
  }
  {
    auto a = ppp::openObservationSource(crx_path);
    auto b = ppp::openLineSource(plain_path);
    std::string la, lb;
    std::size_t diff = 0, n = 0;
    for (;;) {
      const bool ha = a->next(la), hb = b->next(lb);
      if (!ha || !hb) {
        diff += ha != hb;
        break;
      }
      ++n;
      if (la != lb && diff++ < 3) std::printf("  differs at line %zu:\n  crx  '%s'\n  rnx  '%s'\n", n, la.c_str(), lb.c_str());
    }
    std::printf("restored CRX text vs plain file: %zu lines, %zu differing\n", n, diff);
  }
  std::printf("peak RSS at the end: %ld MB (file sizes: %.0f MB plain)\n", peakRssMb(), plain_bytes / 1e6);
  if (argc <= 2) std::filesystem::remove_all(dir);
  return 0;
}
