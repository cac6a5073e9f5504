// Benchmark of the integer least-squares solver (LAMBDA: decorrelation, search,
// ratio test, partial fixing; ppp/ambiguity/integer_least_squares.h) on PPP-like float
// ambiguity problems: n narrow-lane ambiguities [cycles] whose covariance comes
// from a least-squares fit of position, clock and zenith delay plus one bias per
// satellite to code and phase over a few epochs of a random sky, so that the
// ambiguities are strongly correlated through the common receiver terms, as in
// the filter. Prints the per-call cost (median, p99) and the search nodes;
// asserts nothing.
//
//   ppp_bench_ambiguity_search [problems=1000]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "ppp_bayes_tree/ppp/ambiguity/integer_least_squares.h"

namespace {

using Clock = std::chrono::steady_clock;

/// Float ambiguity covariance [NL cycles^2] of n satellites after `epochs` epochs
/// of code (sigma 0.3 m) and phase (3 mm) with unknown position, clock, ZWD.
Eigen::MatrixXd pppLikeCovariance(int n, int epochs, std::mt19937& rng) {
  std::uniform_real_distribution<double> az(0.0, 2.0 * M_PI), el(0.2, 1.5), drift(-0.002, 0.002);
  std::vector<double> a(n), e(n), da(n), de(n);
  for (int i = 0; i < n; ++i) a[i] = az(rng), e[i] = el(rng), da[i] = drift(rng), de[i] = drift(rng);
  const int receiver = 5;  // x, y, z, clock, zwd (new per epoch for position and clock)
  const int dim = epochs * receiver + n;
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(dim, dim);
  const double lambda_nl = 0.107;
  for (int k = 0; k < epochs; ++k) {
    for (int i = 0; i < n; ++i) {
      const double ee = e[i] + de[i] * k * 30.0, aa = a[i] + da[i] * k * 30.0;
      Eigen::VectorXd h = Eigen::VectorXd::Zero(dim);
      h(k * receiver + 0) = -std::cos(ee) * std::sin(aa);
      h(k * receiver + 1) = -std::cos(ee) * std::cos(aa);
      h(k * receiver + 2) = -std::sin(ee);
      h(k * receiver + 3) = 1.0;
      h(k * receiver + 4) = 1.0 / std::sin(ee);
      N += h * h.transpose() / (0.3 * 0.3);  // code
      h(epochs * receiver + i) = lambda_nl;  // phase sees the ambiguity [cycles]
      N += h * h.transpose() / (0.003 * 0.003);
    }
  }
  const Eigen::MatrixXd P = N.ldlt().solve(Eigen::MatrixXd::Identity(dim, dim));
  // A single difference against satellite 0 removes the clock's common part.
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n - 1, dim);
  for (int i = 1; i < n; ++i) D(i - 1, epochs * receiver + i) = 1.0, D(i - 1, epochs * receiver) = -1.0;
  return D * P * D.transpose();
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::min<double>(v.size() - 1, p * (v.size() - 1)))];
}

}  // namespace

int main(int argc, char** argv) {
  const int problems = argc > 1 ? std::atoi(argv[1]) : 1000;
  std::printf("integer least squares on PPP-like problems, %d problems per row\n", problems);
  std::printf("%4s %7s %12s %12s %12s %10s %8s\n", "n", "epochs", "median[us]", "p99[us]", "max[us]",
              "nodes p50", "fixed%");
  std::mt19937 rng(1);
  for (int sats : {7, 9, 11, 13}) {
    for (int epochs : {3, 10, 20}) {
      std::vector<double> us, nodes;
      int fixed = 0;
      for (int p = 0; p < problems; ++p) {
        const Eigen::MatrixXd Q = pppLikeCovariance(sats, epochs, rng);
        const int n = static_cast<int>(Q.rows());
        Eigen::LLT<Eigen::MatrixXd> llt(Q);
        std::normal_distribution<double> g(0.0, 1.0);
        Eigen::VectorXd w(n);
        for (int i = 0; i < n; ++i) w(i) = g(rng);
        const Eigen::VectorXd a_hat = Eigen::VectorXd::Constant(n, 17.0) + llt.matrixL() * w;
        const auto t0 = Clock::now();
        const ppp::IlsResult r = ppp::solveIntegerLeastSquares(a_hat, Q);
        const auto t1 = Clock::now();
        us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
        nodes.push_back(static_cast<double>(r.nodes_visited));
        fixed += r.isFixed() ? 1 : 0;
      }
      std::printf("%4d %7d %12.1f %12.1f %12.1f %10.0f %8.1f\n", sats - 1, epochs, percentile(us, 0.5),
                  percentile(us, 0.99), percentile(us, 1.0), percentile(nodes, 0.5), 100.0 * fixed / problems);
    }
  }
  return 0;
}
