#pragma once
// RandomStream: the simulator's only source of randomness. A std::mt19937_64
// (whose output sequence the C++ standard fixes, [rand.predef]) with our own
// conversions to uniform and normal variates, because the std distributions
// (std::normal_distribution, std::uniform_real_distribution) are
// implementation-defined and would break "same seed -> same files" across
// standard libraries. Normal variates: Box-Muller (Box & Muller 1958), both
// values of a pair used. The transcendental functions come from the C library:
// bit-identical results are guaranteed on one platform (libm), which is what
// the determinism tests check.
//
// Sub-streams: derive(tag) gives an independent stream whose seed is a hash
// (SplitMix64, Steele et al. 2014) of this stream's seed and the tag, so that
// enabling one error term does not shift the random numbers of another.
#include <cmath>
#include <cstdint>
#include <random>

namespace ppp {

class RandomStream {
 public:
  explicit RandomStream(std::uint64_t seed) : seed_(seed), engine_(seed) {}

  std::uint64_t seed() const { return seed_; }
  /// Independent stream for a named purpose (tag: any integer, e.g. a satellite index).
  RandomStream derive(std::uint64_t tag) const { return RandomStream(splitMix64(seed_ ^ splitMix64(tag + 1))); }

  /// Uniform in [0, 1) with 53 random bits.
  double uniform01() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }
  /// Uniform integer in [lo, hi] (rejection sampling: no modulo bias).
  std::int64_t uniformInt(std::int64_t lo, std::int64_t hi) {
    const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
    if (span == 0) return static_cast<std::int64_t>(engine_());
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % span;
    std::uint64_t x;
    do x = engine_();
    while (x >= limit);
    return lo + static_cast<std::int64_t>(x % span);
  }
  /// Standard normal variate (Box-Muller).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform01();
    while (u1 <= 0.0) u1 = uniform01();
    const double u2 = uniform01();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * 3.14159265358979323846 * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }
  double normal(double sigma) { return sigma * normal(); }
  bool bernoulli(double p) { return uniform01() < p; }

  static std::uint64_t splitMix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  }

 private:
  std::uint64_t seed_;
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace ppp
