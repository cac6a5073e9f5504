#include "ppp_bayes_tree/evaluation/monte_carlo_records.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <type_traits>

#include "ppp_bayes_tree/io/parse_error.h"

namespace ppp {
namespace {

constexpr char kMagic[8] = {'P', 'P', 'P', 'M', 'C', 'R', '0', '1'};

class RecordWriter {
 public:
  template <typename T>
  void value(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void text(const std::string& s) {
    value<std::uint64_t>(s.size());
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }
  template <typename T>
  void array(const std::vector<T>& v) {
    value<std::uint64_t>(v.size());
    for (const T& x : v) value(x);
  }
  void raw(const char* p, std::size_t n) { bytes_.insert(bytes_.end(), p, p + n); }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class RecordReader {
 public:
  RecordReader(std::vector<char> bytes, std::string file) : bytes_(std::move(bytes)), file_(std::move(file)) {}
  template <typename T>
  T value() {
    need(sizeof(T), "a value");
    T v;
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string text() {
    const std::uint64_t n = length(1, "a text");
    std::string s(bytes_.data() + at_, bytes_.data() + at_ + n);
    at_ += n;
    return s;
  }
  template <typename T>
  std::vector<T> array() {
    const std::uint64_t n = length(sizeof(T), "an array");
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), bytes_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return v;
  }
  bool atEnd() const { return at_ == bytes_.size(); }
  std::size_t offset() const { return at_; }
  [[noreturn]] void fail(std::size_t offset, const std::string& reason) const {
    throw ParseError(file_, offset, reason + " (at byte " + std::to_string(offset) + ")");
  }

 private:
  void need(std::size_t n, const char* what) const {
    if (bytes_.size() - at_ < n) fail(at_, std::string("truncated: ") + what + " runs past the end of the file");
  }
  std::uint64_t length(std::size_t element, const char* what) {
    const std::size_t where = at_;
    const auto n = value<std::uint64_t>();
    if (n > (bytes_.size() - at_) / element) fail(where, std::string("truncated: ") + what + " of " + std::to_string(n) + " elements runs past the end");
    return n;
  }
  std::vector<char> bytes_;
  std::string file_;
  std::size_t at_ = 0;
};

void writeHeld(RecordWriter& w, const HeldIntegerCheck& h) {
  for (std::size_t v : {h.held, h.wrong, h.cross_system, h.not_compared, h.fixed_epochs, h.fixed_epochs_with_wrong_hold})
    w.value<std::uint64_t>(v);
  w.value(h.max_abs_error_cycles);
}

HeldIntegerCheck readHeld(RecordReader& r) {
  HeldIntegerCheck h;
  for (std::size_t* v : {&h.held, &h.wrong, &h.cross_system, &h.not_compared, &h.fixed_epochs, &h.fixed_epochs_with_wrong_hold})
    *v = r.value<std::uint64_t>();
  h.max_abs_error_cycles = r.value<double>();
  return h;
}

void writeFlight(RecordWriter& w, const MonteCarloFlightRun& f) {
  w.value<std::int32_t>(f.setup.index);
  w.value<std::uint64_t>(f.setup.seed);
  w.text(f.failure);
  w.value<std::uint64_t>(f.drawn.size());
  for (const auto& d : f.drawn) w.text(d);
  for (std::size_t v : {f.epochs, f.simulated_arcs, f.phase_breaks, f.estimator_arcs, f.slips_detected,
                        f.bias_arcs_compared, f.bias_arcs_missed_slip})
    w.value<std::uint64_t>(v);
  w.array(f.time_s);
  for (const auto& e : f.error_3d_m) w.array(e);
  for (const auto& b : f.bias) {
    w.value<std::uint64_t>(b.size());
    for (const auto& s : b) {
      w.value(s.age_s);
      w.value(s.error_m);
    }
  }
  for (const auto& x : f.fixed) w.array(x);
  for (const auto& h : f.held_check) writeHeld(w, h);
  w.array(f.filtered_minus_ekf_m);
}

MonteCarloFlightRun readFlight(RecordReader& r, const MonteCarloOptions& options) {
  const std::size_t start = r.offset();
  MonteCarloFlightRun f;
  const auto index = r.value<std::int32_t>();
  const auto seed = r.value<std::uint64_t>();
  if (index < 0) r.fail(start, "negative flight index " + std::to_string(index));
  f.setup = monteCarloFlightSetup(options, index);
  if (f.setup.seed != seed)
    r.fail(start, "flight " + std::to_string(index) + " has seed " + std::to_string(seed) + ", the study's seed " +
                      std::to_string(options.seed) + " gives " + std::to_string(f.setup.seed) +
                      " (records of another study)");
  f.failure = r.text();
  const auto drawn = r.value<std::uint64_t>();
  for (std::uint64_t i = 0; i < drawn; ++i) f.drawn.push_back(r.text());
  for (std::size_t* v : {&f.epochs, &f.simulated_arcs, &f.phase_breaks, &f.estimator_arcs, &f.slips_detected,
                         &f.bias_arcs_compared, &f.bias_arcs_missed_slip})
    *v = r.value<std::uint64_t>();
  f.time_s = r.array<double>();
  for (auto& e : f.error_3d_m) e = r.array<double>();
  for (auto& b : f.bias) {
    const auto n = r.value<std::uint64_t>();
    if (n > (1u << 30)) r.fail(r.offset(), "implausible bias sample count " + std::to_string(n));
    b.resize(n);
    for (auto& s : b) {
      s.age_s = r.value<float>();
      s.error_m = r.value<float>();
    }
  }
  for (auto& x : f.fixed) x = r.array<char>();
  for (auto& h : f.held_check) h = readHeld(r);
  f.filtered_minus_ekf_m = r.array<double>();
  return f;
}

}  // namespace

void writeMonteCarloFlightRecords(const std::vector<MonteCarloFlightRun>& flights, const std::string& path) {
  RecordWriter w;
  w.raw(kMagic, sizeof kMagic);
  w.value<std::uint32_t>(static_cast<std::uint32_t>(flights.size()));
  for (const auto& f : flights) writeFlight(w, f);
  std::ofstream out(path, std::ios::binary);
  out.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::vector<MonteCarloFlightRun> readMonteCarloFlightRecords(const std::string& path,
                                                             const MonteCarloOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileOpenError("cannot open Monte Carlo records " + path);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  RecordReader r(std::move(bytes), path);
  char magic[sizeof kMagic];
  for (char& c : magic) c = r.value<char>();
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) r.fail(0, "not Monte Carlo flight records (magic PPPMCR01 expected)");
  const auto count = r.value<std::uint32_t>();
  std::vector<MonteCarloFlightRun> flights;
  for (std::uint32_t i = 0; i < count; ++i) flights.push_back(readFlight(r, options));
  if (!r.atEnd()) r.fail(r.offset(), "bytes after the last of " + std::to_string(count) + " flights");
  return flights;
}

MonteCarloResult mergeMonteCarloShards(const MonteCarloOptions& study,
                                       std::vector<std::vector<MonteCarloFlightRun>> shards) {
  MonteCarloResult result;
  result.options = study;
  result.options.first_flight = 0;
  const auto n = static_cast<std::size_t>(std::max(0, study.flights));
  result.flights.resize(n);
  std::vector<char> seen(n, 0);
  for (auto& shard : shards) {
    for (auto& f : shard) {
      const int i = f.setup.index;
      if (i < 0 || static_cast<std::size_t>(i) >= n)
        throw std::invalid_argument("flight " + std::to_string(i) + " is outside the study's " + std::to_string(n) +
                                    " flights");
      if (seen[static_cast<std::size_t>(i)]++)
        throw std::invalid_argument("flight " + std::to_string(i) + " is in more than one shard");
      result.flights[static_cast<std::size_t>(i)] = std::move(f);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!seen[i]) throw std::invalid_argument("flight " + std::to_string(i) + " is in no shard");
  result.summary = summarizeMonteCarlo(result.flights, result.options);
  return result;
}

}  // namespace ppp
