// Benchmark of the iSAM2 smoother on a synthetic graph shaped like kinematic PPP: 1 Hz
// epochs, a 5-dim state per epoch (position, clock, zenith delay) linked by a between
// factor, about 10 visible satellites, one bias variable per satellite arc (arcs of 30 min
// to 4 h), and two measurement factors per satellite and epoch (code: state only; phase:
// state + arc bias). Prints figures; asserts nothing.
//
//   ppp_bench_isam2 [epochs=20000]
//
// Each scenario runs in its own child process so that its peak memory (VmHWM) is its own.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include "ppp_bayes_tree/smoother/batch_solver.h"
#include "ppp_bayes_tree/smoother/between_factor.h"
#include "ppp_bayes_tree/smoother/fixed_lag_smoother.h"
#include "ppp_bayes_tree/smoother/isam2.h"
#include "ppp_bayes_tree/smoother/noise_model_factor_n.h"
#include "ppp_bayes_tree/smoother/prior_factor.h"

using namespace ppp::smoother;

namespace {

using Clock = std::chrono::steady_clock;

// Range-like measurement: z = |sat - p| + clock + m * zenith_delay (code), + bias (phase).
struct RangeModel {
  Eigen::Vector3d sat;
  double m, z;
  double predict(const Vector& s, Matrix* h) const {
    const Eigen::Vector3d d = s.head<3>() - sat;
    const double r = d.norm();
    if (h) {
      Matrix hs(1, 5);
      hs << d.x() / r, d.y() / r, d.z() / r, 1.0, m;
      *h = hs;
    }
    return r + s[3] + m * s[4];
  }
};

class CodeRangeFactor : public NoiseModelFactor1<Vector> {
 public:
  CodeRangeFactor(Key state, RangeModel model, NoiseModel::Ptr noise)
      : NoiseModelFactor1<Vector>(std::move(noise), {state}), model_(model) {}
  Vector evaluateError(const Vector& s, Matrix* h) const override {
    return Vector::Constant(1, model_.predict(s, h) - model_.z);
  }

 private:
  RangeModel model_;
};

class PhaseRangeFactor : public NoiseModelFactor2<Vector, double> {
 public:
  PhaseRangeFactor(Key state, Key bias, RangeModel model, NoiseModel::Ptr noise)
      : NoiseModelFactor2<Vector, double>(std::move(noise), {state, bias}), model_(model) {}
  Vector evaluateError(const Vector& s, const double& b, Matrix* hs, Matrix* hb) const override {
    if (hb) *hb = Matrix::Ones(1, 1);
    return Vector::Constant(1, model_.predict(s, hs) + b - model_.z);
  }

 private:
  RangeModel model_;
};

struct Epoch {
  NonlinearFactorGraph factors;
  Values values;
  KeyVector newest;
  Key state;
  double time_s;
};

// Deterministic PPP-shaped scenario generator.
class Scenario {
 public:
  static constexpr int kSlots = 10;
  Scenario() : rng_(12345) {
    for (int s = 0; s < kSlots; ++s) {
      arc_[s] = -1;
      end_[s] = -1;
      offset_[s] = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng_);
    }
    code_ = NoiseModel::isotropic(1, 0.3);
    phase_ = NoiseModel::isotropic(1, 0.003);
    Vector q(5);
    q << 0.05, 0.05, 0.05, 10.0, 1e-4;  // kinematic position, white-ish clock, slow ZTD
    walk_ = NoiseModel::sigmas(q);
  }

  Vector truth(int t) const {
    Vector s(5);
    s << 5.0 * std::sin(1e-3 * t), 3.0 * std::cos(7e-4 * t), 0.01 * t * 1e-2, 100.0 + 0.5 * std::sin(0.01 * t), 2.3;
    return s;
  }

  Epoch next(int t) {
    Epoch e;
    e.time_s = t;
    e.state = symbolKey('x', static_cast<std::uint32_t>(t));
    std::normal_distribution<double> n01;
    Vector guess = truth(t);
    for (int i = 0; i < 5; ++i) guess[i] += (i < 3 ? 0.5 : 1.0) * n01(rng_);
    e.values.insert(e.state, guess);
    e.newest.push_back(e.state);
    if (t == 0) {
      Vector sig(5);
      sig << 10, 10, 10, 100, 0.5;
      e.factors.push_back(std::make_shared<PriorFactor>(e.state, guess, NoiseModel::sigmas(sig)));
    } else {
      e.factors.push_back(std::make_shared<BetweenFactor>(symbolKey('x', static_cast<std::uint32_t>(t - 1)), e.state,
                                                          truth(t) - truth(t - 1), walk_));
    }
    for (int s = 0; s < kSlots; ++s) {
      if (t > end_[s]) {  // a new arc: 30 min to 4 h (the first ones start part-way)
        ++arc_[s];
        const int len = std::uniform_int_distribution<int>(1800, 14400)(rng_);
        end_[s] = t + (t == 0 ? std::uniform_int_distribution<int>(60, len)(rng_) : len);
        bias_value_[s] = std::uniform_real_distribution<double>(-20, 20)(rng_);
        e.values.insert(biasKey(s), Vector::Zero(1));
      }
      const Key b = biasKey(s);
      // Satellite on a slowly rotating direction, 20,000 km away, elevation 15..75 deg.
      const double az = offset_[s] + 2 * M_PI * t / 43200.0 + arc_[s];
      const double el = 0.26 + 0.5 * (1 + std::sin(offset_[s] + t / 7000.0 + arc_[s]));
      const Eigen::Vector3d sat = 2.0e7 * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const double m = 1.0 / std::sin(el);
      const Vector x = truth(t);
      const double rho = (sat - x.head<3>()).norm() + x[3] + m * x[4];
      e.factors.push_back(std::make_shared<CodeRangeFactor>(e.state, RangeModel{sat, m, rho + 0.3 * n01(rng_)}, code_));
      e.factors.push_back(
          std::make_shared<PhaseRangeFactor>(e.state, b, RangeModel{sat, m, rho + bias_value_[s] + 0.003 * n01(rng_)}, phase_));
      e.newest.push_back(b);
    }
    return e;
  }

 private:
  Key biasKey(int s) const {
    const std::string label = "G" + std::to_string(10 + s);
    return symbolKey('b', label, static_cast<std::uint32_t>(arc_[s]));
  }
  std::mt19937 rng_;
  int arc_[kSlots];
  int end_[kSlots];
  double offset_[kSlots];
  double bias_value_[kSlots];
  NoiseModel::Ptr code_, phase_, walk_;
};

long statusKb(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field, 0) == 0) return std::atol(line.c_str() + std::string(field).size());
  return -1;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

struct Window {
  int begin, end;
};

void runSmoother(int epochs, double lag_s, Window early, Window late) {
  Scenario sc;
  ISAM2Params params;  // defaults: Cholesky, relinearize 0.1 every 10, wildfire 1e-3
  std::unique_ptr<ISAM2> isam;
  std::unique_ptr<FixedLagSmoother> fl;
  if (lag_s > 0) fl = std::make_unique<FixedLagSmoother>(FixedLagParams{lag_s, params});
  else isam = std::make_unique<ISAM2>(params);
  std::vector<double> ms(epochs), reelim(epochs), touched(epochs);
  std::array<double, ISAM2Result::kNumSteps> step_sum{};
  std::size_t relin_total = 0, marg_total = 0, moved_updates = 0, relin_updates = 0;
  const auto t0 = Clock::now();
  std::printf("  %-8s %10s %10s %10s\n", "epoch", "VmRSS[MB]", "vars", "factors");
  for (int t = 0; t < epochs; ++t) {
    Epoch e = sc.next(t);
    const auto a = Clock::now();
    ISAM2Result r;
    if (fl) {
      const FixedLagResult fr = fl->update(e.factors, e.values, {{e.state, e.time_s}}, e.newest);
      r = fr.isam2;
      marg_total += fr.variables_marginalized;
      if (fr.variables_moved_to_leaves) ++moved_updates;
    } else {
      ISAM2UpdateParams up;
      up.newest_keys = e.newest;
      r = isam->update(e.factors, e.values, up);
    }
    ms[t] = std::chrono::duration<double, std::milli>(Clock::now() - a).count();
    reelim[t] = static_cast<double>(r.variables_reeliminated);
    touched[t] = static_cast<double>(r.cliquesTouched());
    relin_total += r.variables_relinearized;
    if (r.variables_relinearized) ++relin_updates;
    for (std::size_t i = 0; i < step_sum.size(); ++i) step_sum[i] += r.step_time_s[i];
    if ((t + 1) % std::max(1, epochs / 10) == 0 || t + 1 == epochs) {
      const ISAM2& is = fl ? fl->isam2() : *isam;
      std::printf("  %-8d %10.1f %10zu %10zu\n", t + 1, statusKb("VmRSS:") / 1024.0, is.linearizationPoint().size(),
                  is.numFactors());
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  auto slice = [&](const std::vector<double>& v, Window w) {
    return std::vector<double>(v.begin() + w.begin, v.begin() + w.end);
  };
  std::printf("  update time [ms]  epochs %5d-%5d: median %.3f  p99 %.3f  max %.3f\n", early.begin, early.end,
              quantile(slice(ms, early), 0.5), quantile(slice(ms, early), 0.99), quantile(slice(ms, early), 1.0));
  std::printf("  update time [ms]  epochs %5d-%5d: median %.3f  p99 %.3f  max %.3f\n", late.begin, late.end,
              quantile(slice(ms, late), 0.5), quantile(slice(ms, late), 0.99), quantile(slice(ms, late), 1.0));
  std::printf("  variables re-eliminated per update (all epochs): median %.0f  p99 %.0f  max %.0f\n",
              quantile(reelim, 0.5), quantile(reelim, 0.99), quantile(reelim, 1.0));
  std::printf("  variables re-eliminated, late window: median %.0f  p99 %.0f\n", quantile(slice(reelim, late), 0.5),
              quantile(slice(reelim, late), 0.99));
  std::printf("  cliques touched per update: median %.0f  p99 %.0f\n", quantile(touched, 0.5), quantile(touched, 0.99));
  std::printf("  variables relinearized (total): %zu in %zu updates; marginalized (total): %zu; updates that "
              "re-eliminated due variables to the leaves: %zu\n", relin_total, relin_updates, marg_total, moved_updates);
  std::printf("  mean time per step [us]: ");
  for (std::size_t i = 0; i < step_sum.size(); ++i)
    std::printf("%zu %s:%.1f  ", i + 1, ISAM2Result::kStepNames[i], 1e6 * step_sum[i] / epochs);
  std::printf("\n  total wall time %.2f s, peak memory VmHWM %.1f MB\n", wall, statusKb("VmHWM:") / 1024.0);
  const ISAM2& is = fl ? fl->isam2() : *isam;
  std::printf("  final tree: %zu cliques, depth %zu, root clique %zu variables\n", is.bayesTree().numCliques(),
              is.bayesTree().depth(), is.bayesTree().roots().empty() ? 0 : is.bayesTree().roots()[0]->frontals.size());
}

void runBatch(int epochs) {
  Scenario sc;
  NonlinearFactorGraph graph;
  Values values;
  std::vector<int> marks;
  for (int n : {1000, 5000, 20000})
    if (n <= epochs) marks.push_back(n);
  if (marks.empty() || marks.back() != epochs) marks.push_back(epochs);
  std::size_t next = 0;
  for (int t = 0; t < epochs && next < marks.size(); ++t) {
    Epoch e = sc.next(t);
    for (auto& f : e.factors) graph.push_back(f);
    for (const auto& [k, v] : e.values) values.insert(k, v);
    if (t + 1 == marks[next]) {
      const auto a = Clock::now();
      const GaussianFactorGraph lin = linearizeGraph(graph, values);
      const double lin_s = std::chrono::duration<double>(Clock::now() - a).count();
      const Values delta = solveLinear(lin, values);
      const double all_s = std::chrono::duration<double>(Clock::now() - a).count();
      std::printf("  batch re-solve at %6d epochs (%zu variables, dim %zu, %zu factors): linearize %.3f s, "
                  "total one Gauss-Newton step %.3f s\n",
                  t + 1, values.size(), values.dim(), graph.size(), lin_s, all_s);
      ++next;
    }
  }
  std::printf("  peak memory VmHWM %.1f MB\n", statusKb("VmHWM:") / 1024.0);
}

template <typename F>
void inChild(const char* title, F f) {
  std::printf("\n== %s\n", title);
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    f();
    std::fflush(stdout);
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) std::printf("  (scenario failed, status %d)\n", status);
}

}  // namespace

int main(int argc, char** argv) {
  const int epochs = argc > 1 ? std::max(100, std::atoi(argv[1])) : 20000;
  const Window early = epochs >= 3000 ? Window{1000, 2000} : Window{epochs / 4, epochs / 2};
  const Window late = epochs >= 3000 ? Window{epochs - 1000, epochs} : Window{epochs - epochs / 4, epochs};
  std::printf("ppp_bench_isam2: %d epochs at 1 Hz, %d satellites, 2 factors per satellite and epoch\n", epochs,
              Scenario::kSlots);
  inChild("iSAM2, full smoother (no marginalization)", [&] { runSmoother(epochs, 0.0, early, late); });
  inChild("iSAM2, fixed lag 600 s", [&] { runSmoother(epochs, 600.0, early, late); });
  inChild("batch re-solve for contrast (CHOLMOD)", [&] { runBatch(epochs); });
  return 0;
}
