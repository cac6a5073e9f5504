// ppp_sim_error_budget: per-term error budget of simulated flights. Runs Monte
// Carlo flights (the same setup as ppp_monte_carlo: flight seed, start, origin,
// profile, the study's default estimator configuration unless --config) with the
// simulator's error terms switched off one at a time, and prints per estimator
// (EKF, smoother filtered, smoother smoothed) the mean (sd) of the position error
// per ENU component [cm], the rms of error / formal sigma (filtered solutions),
// the smoothed ZWD error, the smoothed formal sigmas at mid-flight and the
// last-epoch error/sigma: a systematic offset can be traced to an error term or
// to an estimator prior (how the 1 m start prior was found, monte_carlo.h).
//
// usage: ppp_sim_error_budget --seed S [--flight I] [--count N] [--profile figure8]
//                             [--duration-min 25] [--rate 1] [--config PPP_YAML]
//                             [--sim-config SIMULATION_YAML] [--after-min 0]
//                             [--scenarios all,none,-thermal,+multipath+phase_breaks,...]
//                             [--zwd-truth 1]
// Scenarios: "all" every term as configured; "none" every term off; "-a-b" all
// but a and b; "+a+b" only a and b (terms: thermal, multipath, troposphere,
// ionosphere, receiver_clock, ambiguity, phase_breaks, products). --zwd-truth 1:
// the estimators' a-priori ZWD is the flight's true ZWD with sigma 1 mm
// (diagnostic: removes the height/ZWD ambiguity).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"
#include "ppp_bayes_tree/models/troposphere.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/frames.h"

namespace {

using namespace ppp;

const std::vector<std::string> kTerms = {"thermal",        "multipath", "troposphere", "ionosphere",
                                         "receiver_clock", "ambiguity", "phase_breaks", "products"};

bool& termFlag(ErrorModelConfig& e, const std::string& t) {
  if (t == "thermal") return e.thermal.enabled;
  if (t == "multipath") return e.multipath.enabled;
  if (t == "troposphere") return e.troposphere.enabled;
  if (t == "ionosphere") return e.ionosphere.enabled;
  if (t == "receiver_clock") return e.receiver_clock.enabled;
  if (t == "ambiguity") return e.ambiguity.enabled;
  if (t == "phase_breaks") return e.phase_breaks.enabled;
  if (t == "products") return e.products.enabled;
  throw std::invalid_argument("unknown error term " + t);
}

ErrorModelConfig scenarioErrors(ErrorModelConfig base, const std::string& s) {
  if (s == "all") return base;
  if (s == "none") {
    for (const auto& t : kTerms) termFlag(base, t) = false;
    return base;
  }
  // "-a-b": all but a and b; "+a+b": only a and b (as configured).
  if (s.size() > 1 && (s[0] == '-' || s[0] == '+')) {
    const char sep = s[0];
    std::vector<std::string> names;
    std::stringstream ss(s.substr(1));
    for (std::string t; std::getline(ss, t, sep);) names.push_back(t);
    const ErrorModelConfig configured = base;
    if (sep == '+')
      for (const auto& t : kTerms) termFlag(base, t) = false;
    for (const auto& t : names) termFlag(base, t) = sep == '+' ? termFlag(const_cast<ErrorModelConfig&>(configured), t) : false;
    return base;
  }
  throw std::invalid_argument("unknown scenario " + s);
}

struct Accumulator {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d nees = Eigen::Vector3d::Zero();  // sum of (error / formal sigma)^2 per ENU component
  std::size_t nees_n = 0;
  void addNormalized(const Eigen::Vector3d& enu, const Eigen::Vector3d& sigma_enu) {
    if (!(sigma_enu.minCoeff() > 0.0)) return;
    nees += enu.cwiseQuotient(sigma_enu).cwiseAbs2();
    ++nees_n;
  }
  double sum3d = 0.0;
  std::size_t n = 0;
  void add(const Eigen::Vector3d& enu) {
    sum += enu;
    sum2 += enu.cwiseProduct(enu);
    sum3d += enu.norm();
    ++n;
  }
  std::string text() const {
    if (n == 0) return "no solution";
    const Eigen::Vector3d m = sum / static_cast<double>(n);
    const Eigen::Vector3d sd = (sum2 / static_cast<double>(n) - m.cwiseProduct(m)).cwiseMax(0.0).cwiseSqrt();
    char b[200];
    std::snprintf(b, sizeof b, "E %6.1f (%5.1f)  N %6.1f (%5.1f)  U %6.1f (%5.1f)  3D %6.1f", 100 * m.x(), 100 * sd.x(),
                  100 * m.y(), 100 * sd.y(), 100 * m.z(), 100 * sd.z(), 100 * sum3d / static_cast<double>(n));
    std::string out = b;
    if (nees_n > 0) {
      const Eigen::Vector3d r = (nees / static_cast<double>(nees_n)).cwiseSqrt();
      std::snprintf(b, sizeof b, "  rms(err/sigma) E %.1f N %.1f U %.1f", r.x(), r.y(), r.z());
      out += b;
    }
    return out;
  }
};

Eigen::Vector3d enuSigma(const ReceiverCovariance& c, const Eigen::Vector3d& truth) {
  const Geodetic g = ecefToGeodetic(truth);
  const Eigen::Matrix3d r = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
  return (r * c.topLeftCorner<3, 3>() * r.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
}

Eigen::Vector3d enuError(const Eigen::Vector3d& est, const Eigen::Vector3d& truth) {
  const Geodetic g = ecefToGeodetic(truth);
  return rotationEnuFromEcef(g.latitude_rad, g.longitude_rad) * (est - truth);
}

constexpr const char* kUsage =
    "usage: ppp_sim_error_budget --seed S [--flight I] [--count N] [--profile figure8]\n"
    "                            [--duration-min 25] [--rate 1] [--config PPP_YAML]\n"
    "                            [--sim-config SIMULATION_YAML] [--after-min 0]\n"
    "                            [--scenarios all,none,-thermal,+multipath+phase_breaks,...]\n"
    "                            [--zwd-truth 1]\n"
    "Scenarios: \"all\" every term as configured; \"none\" every term off; \"-a-b\" all but a and b;\n"
    "\"+a+b\" only a and b (terms: thermal, multipath, troposphere, ionosphere, receiver_clock,\n"
    "ambiguity, phase_breaks, products).\n";

}  // namespace

int main(int argc, char** argv) {
  MonteCarloOptions options;
  options.duration_s = 25 * 60.0;
  int flight = 0, count = 1;
  double after_min = 0.0;
  std::string scenarios = "all,none";
  bool zwd_truth = false;  // diagnostic: the estimators' ZWD prior = the truth, sigma 1 mm
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  if ((argc - 1) % 2 != 0) {
    std::fprintf(stderr, "option %s has no value\n%s", argv[argc - 1], kUsage);
    return 2;
  }
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--seed") options.seed = std::strtoull(v.c_str(), nullptr, 10);
    else if (a == "--flight") flight = std::atoi(v.c_str());
    else if (a == "--count") count = std::atoi(v.c_str());
    else if (a == "--profile") options.profiles = {parseFlightProfile(v)};
    else if (a == "--duration-min") options.duration_s = std::atof(v.c_str()) * 60.0;
    else if (a == "--rate") options.rate_hz = std::atof(v.c_str());
    else if (a == "--config") options.ppp = loadPppConfig(v);
    else if (a == "--sim-config") options.simulation = loadSimulationConfig(v);
    else if (a == "--scenarios") scenarios = v;
    else if (a == "--zwd-truth") zwd_truth = v == "1";
    else if (a == "--after-min") after_min = std::atof(v.c_str());
    else {
      std::cerr << "unknown option " << a << "\n" << kUsage;
      return 2;
    }
  }
  for (int fi = flight; fi < flight + count; ++fi) {
  const MonteCarloFlightSetup setup = monteCarloFlightSetup(options, fi);
  std::printf("flight %d seed %llu profile %s lat %.2f lon %.2f h %.0f start %s\n", fi,
              static_cast<unsigned long long>(setup.seed), flightProfileName(setup.profile),
              setup.origin.latitude_rad / kDegToRad, setup.origin.longitude_rad / kDegToRad, setup.origin.height_m,
              setup.start.toString(TimeSystem::GPS, 0).c_str());
  std::printf("mean (sd) of the ENU error [cm], epochs after %.1f min\n", after_min);
  std::stringstream ss(scenarios);
  std::string sc;
  while (std::getline(ss, sc, ',')) {
    SimulationConfig sim = monteCarloSimulationConfig(options, setup);
    sim.errors = scenarioErrors(sim.errors, sc);
    const SimulatedFlight f = simulateFlight(sim, setup.seed);
    PppConfig c = flightPppConfig(options.ppp, f);  // the flight's physics, the config's weights
    // The true ZWD in the estimators' convention: at the receiver, or carried to the ellipsoid.
    auto stateZwd_m = [&](const TruthEpoch& e) {
      if (!c.model.zwd_at_ellipsoid) return e.zwd_m;
      return e.zwd_m / standardWetDelayHeightRatio(ecefToGeodetic(e.trajectory.position_ecef_m).height_m);
    };
    if (zwd_truth) {
      c.stochastic.initial_zwd_m = stateZwd_m(f.truth.front());
      c.stochastic.zwd.initial_sigma_m = 0.001;
    }
    PppInMemoryInputs in;
    in.header = &f.header;
    in.epochs = &f.epochs;
    in.products = &f.products;
    in.name = sc;
    const GnssTime t0 = f.epochs.front().time;
    auto truthEpoch = [&](const GnssTime& t) -> const TruthEpoch* {
      const auto k = static_cast<std::size_t>(std::llround((t - t0) * options.rate_hz));
      if (k < f.truth.size() && f.truth[k].trajectory.time == t) return &f.truth[k];
      return nullptr;
    };
    auto truthAt = [&](const GnssTime& t) -> const Eigen::Vector3d* {
      const TruthEpoch* e = truthEpoch(t);
      return e ? &e->trajectory.position_ecef_m : nullptr;
    };
    double zwd_err_sum = 0.0;
    std::size_t zwd_n = 0;
    Accumulator ekf_acc, filt_acc, smooth_acc;
    Eigen::Vector3d ekf_last_err = Eigen::Vector3d::Zero(), ekf_last_sigma = Eigen::Vector3d::Zero();
    {
      PppPipeline pipeline(in, c);
      const std::unique_ptr<PppEstimator> ekf = makeEstimator("ekf", c);
      pipeline.run(*ekf, [&](const PppEpochRecord& rec) {
        const Eigen::Vector3d* tr = truthAt(rec.solution.time);
        if (tr && rec.solution.position_ecef_m && rec.solution.time - t0 >= after_min * 60.0)
        {
          ekf_acc.add(enuError(*rec.solution.position_ecef_m, *tr));
          ekf_acc.addNormalized(enuError(*rec.solution.position_ecef_m, *tr), enuSigma(rec.receiver_covariance, *tr));
          ekf_last_err = enuError(*rec.solution.position_ecef_m, *tr);
          ekf_last_sigma = enuSigma(rec.receiver_covariance, *tr);
        }
      });
    }
    {
      PppPipeline pipeline(in, c);
      const std::unique_ptr<PppEstimator> sm = makeEstimator("smoother", c);
      const PppRunSummary sum = pipeline.run(*sm, [&](const PppEpochRecord& rec) {
        const Eigen::Vector3d* tr = truthAt(rec.solution.time);
        if (tr && rec.solution.position_ecef_m && rec.solution.time - t0 >= after_min * 60.0)
        {
          filt_acc.add(enuError(*rec.solution.position_ecef_m, *tr));
          filt_acc.addNormalized(enuError(*rec.solution.position_ecef_m, *tr), enuSigma(rec.receiver_covariance, *tr));
        }
      });
      std::printf("  estimator arcs %zu slips %zu gaps %zu solved %zu/%zu;", sum.arcs, sum.slips, sum.data_gaps,
                  sum.epochs_solved, sum.epochs_read);
      for (const auto& [why, n] : sum.rejection_counts) std::printf(" %s: %zu", toString(why).c_str(), n);
      std::printf("\n");
      // Formal sigmas (ENU, ZWD) of the smoothed state in the middle of the flight.
      {
        const auto traj = sm->smoothing()->smoothedTrajectory(true);
        const SmoothedEpoch& last = traj.back();
        if (last.covariance && truthAt(last.time)) {
          const Eigen::Vector3d* tr = truthAt(last.time);
          const Eigen::Vector3d e = enuError(last.state.position_ecef_m, *tr), sg = enuSigma(*last.covariance, *tr);
          std::printf("  last epoch [cm]: EKF error U %.1f sigma U %.1f | smoother error U %.1f sigma U %.1f\n",
                      100 * ekf_last_err.z(), 100 * ekf_last_sigma.z(), 100 * e.z(), 100 * sg.z());
        }
        const SmoothedEpoch& mid = traj[traj.size() / 2];
        if (mid.covariance) {
          const Geodetic g = ecefToGeodetic(mid.state.position_ecef_m);
          const Eigen::Matrix3d r = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
          const Eigen::Matrix3d c = r * mid.covariance->topLeftCorner<3, 3>() * r.transpose();
          std::printf("  smoothed formal sigma at mid-flight [cm]: E %.1f N %.1f U %.1f ZWD %.1f, corr(U,ZWD) %.2f\n",
                      100 * std::sqrt(c(0, 0)), 100 * std::sqrt(c(1, 1)), 100 * std::sqrt(c(2, 2)),
                      100 * std::sqrt((*mid.covariance)(3, 3)),
                      (r.row(2) * mid.covariance->block<3, 1>(0, 3))(0) / std::sqrt(c(2, 2) * (*mid.covariance)(3, 3)));
        }
      }
      for (const auto& s : sm->smoothing()->smoothedTrajectory()) {
        const Eigen::Vector3d* tr = truthAt(s.time);
        if (tr && s.time - t0 >= after_min * 60.0) {
          smooth_acc.add(enuError(s.state.position_ecef_m, *tr));
          zwd_err_sum += s.state.zwd_m - stateZwd_m(*truthEpoch(s.time));
          ++zwd_n;
        }
      }
    }
    std::printf("%-16s breaks %4zu arcs %4zu smoothed ZWD error %.1f cm\n  EKF      %s\n  filtered %s\n  smoothed %s\n", sc.c_str(),
                f.breaks.size(), f.arcs.size(), zwd_n ? 100 * zwd_err_sum / zwd_n : 0.0, ekf_acc.text().c_str(), filt_acc.text().c_str(),
                smooth_acc.text().c_str());
    std::fflush(stdout);
  }
  }
  return 0;
}
