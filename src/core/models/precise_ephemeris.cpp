#include "ppp_bayes_tree/models/precise_ephemeris.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "ppp_bayes_tree/models/product_sanity.h"
#include "ppp_bayes_tree/models/relativity.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

std::string timeText(const GnssTime& t) { return t.toString(TimeSystem::GPS, 0); }

std::string minutesText(double seconds) { return format("%.1f min", seconds / 60.0); }

std::string secondsText(double seconds) { return format("%.1f s", seconds); }

/// Most nodes of a Lagrange window (PreciseEphemerisOptions::interpolation_points is clamped to it).
constexpr std::size_t kMaxWindowNodes = 30;

/// Lagrange basis values w[j] = l_j(x) and derivatives dw[j] = l_j'(x) for the
/// nodes tau[0..n-1] (distinct), n <= kMaxWindowNodes. Plain products: n is small
/// (~10). Each factor (x - tau_m) / (tau_j - tau_m) and 1 / (tau_j - tau_k) is
/// computed once and reused by every product that needs it; the products of one j
/// are formed side by side (independent chains the processor overlaps), each with
/// its factors in the order of m. A skipped factor is a multiplication by exactly 1
/// or none, so every value is the one of the plain nested loops, bit for bit.
/// N > 0: the window has exactly N nodes (n == N), known when compiling, so that the
/// side-by-side products stay in registers; N == 0: any n.
template <std::size_t N>
void lagrangeWeights(const double* tau, std::size_t n_any, double x, double* w, double* dw) {
  const std::size_t n = N > 0 ? N : n_any;
  double ratio[kMaxWindowNodes][kMaxWindowNodes];  // (x - tau_m) / (tau_j - tau_m); 1 on the diagonal
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t m = 0; m < n; ++m) ratio[j][m] = m == j ? 1.0 : (x - tau[m]) / (tau[j] - tau[m]);
  // w[j] = prod_{m != j} ratio[j][m]
  for (std::size_t j = 0; j < n; ++j) w[j] = 1.0;
  for (std::size_t m = 0; m < n; ++m)
    for (std::size_t j = 0; j < n; ++j) w[j] *= ratio[j][m];
  // l_j'(x) = sum_{k != j} [1/(tau_j - tau_k)] prod_{m != j,k} (x - tau_m)/(tau_j - tau_m);
  // 1/(tau_k - tau_j) = -1/(tau_j - tau_k) exactly (a - b = -(b - a) in floating point).
  double inverse[kMaxWindowNodes][kMaxWindowNodes];
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t k = j + 1; k < n; ++k) {
      inverse[j][k] = 1.0 / (tau[j] - tau[k]);
      inverse[k][j] = -inverse[j][k];
    }
  double q[kMaxWindowNodes];
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t k = 0; k < n; ++k) q[k] = k == j ? 0.0 : inverse[j][k];
    for (std::size_t m = 0; m < n; ++m) {
      // Every k but m: the factor of k == m is exactly 1 (x * 1 == x for every x).
      const double r = ratio[j][m];
      for (std::size_t k = 0; k < n; ++k) q[k] *= k == m ? 1.0 : r;
    }
    double d = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      if (k != j) d += q[k];
    }
    dw[j] = d;
  }
}

/// lagrangeWeights for any n, with the default window size compiled for its size.
void lagrangeWeights(const double* tau, std::size_t n, double x, double* w, double* dw) {
  if (n == 10) return lagrangeWeights<10>(tau, n, x, w, dw);
  lagrangeWeights<0>(tau, n, x, w, dw);
}

/// Components in the non-rotating frame that coincides with ECEF at the query
/// time, of an ECEF vector taken dt_s after it: rotation by +omega*dt about z.
/// The rotation of rotateToQueryFrame by its cosine and sine.
Eigen::Vector3d rotateAboutZ(const Eigen::Vector3d& v, double c, double s) {
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}

Eigen::Vector3d rotateToQueryFrame(const Eigen::Vector3d& v, double dt_s) {
  const double th = kEarthRotationRate_radps * dt_s;
  return rotateAboutZ(v, std::cos(th), std::sin(th));
}

/// omega x r for the Earth rotation vector (0, 0, omega).
Eigen::Vector3d earthRotationCross(const Eigen::Vector3d& r) {
  return {-kEarthRotationRate_radps * r.y(), kEarthRotationRate_radps * r.x(), 0.0};
}

template <class Node>
void mergeSeries(std::vector<Node>& into, const std::vector<Node>& add, ParseReport& report,
                 bool (*valid)(const Node&)) {
  const auto by_time = [](const Node& a, const Node& b) { return a.time < b.time; };
  into.insert(into.end(), add.begin(), add.end());
  std::stable_sort(into.begin(), into.end(), by_time);
  std::vector<Node> out;
  out.reserve(into.size());
  for (const Node& n : into) {
    if (!out.empty() && out.back().time == n.time) {
      report.count("overlapping epochs de-duplicated");
      if (!valid(out.back()) && valid(n)) out.back() = n;  // keep the first valid one
      continue;
    }
    out.push_back(n);
  }
  into.swap(out);
}

double modalSpacing_s(const std::vector<GnssTime>& times) {
  std::map<long long, std::size_t> hist;
  for (std::size_t i = 1; i < times.size(); ++i) ++hist[std::llround((times[i] - times[i - 1]) * 1000.0)];
  if (hist.empty()) return 0.0;
  const auto best = std::max_element(hist.begin(), hist.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  return static_cast<double>(best->first) * 1e-3;
}

void extendSpan(std::optional<ProductSpan>& span, const GnssTime& first, const GnssTime& last) {
  if (!span) {
    span = ProductSpan{first, last};
    return;
  }
  if (first < span->first) span->first = first;
  if (last > span->last) span->last = last;
}

}  // namespace

std::string_view productStatusName(ProductStatus status) {
  switch (status) {
    case ProductStatus::Ok: return "ok";
    case ProductStatus::NoProducts: return "no products";
    case ProductStatus::SatelliteNotInProducts: return "satellite not in products";
    case ProductStatus::OutsideSpan: return "outside product span";
    case ProductStatus::Gap: return "gap";
    case ProductStatus::BadValueMarker: return "bad value marker";
    case ProductStatus::NotEnoughNodes: return "not enough nodes";
  }
  return "?";
}

EphemerisUnavailable ephemerisUnavailable(ProductStatus status) {
  switch (status) {
    case ProductStatus::Ok:
    case ProductStatus::NoProducts: return EphemerisUnavailable::NoProducts;
    case ProductStatus::SatelliteNotInProducts: return EphemerisUnavailable::SatelliteNotInProducts;
    case ProductStatus::OutsideSpan: return EphemerisUnavailable::OutsideSpan;
    case ProductStatus::Gap: return EphemerisUnavailable::Gap;
    case ProductStatus::BadValueMarker: return EphemerisUnavailable::BadValueMarker;
    case ProductStatus::NotEnoughNodes: return EphemerisUnavailable::NotEnoughNodes;
  }
  return EphemerisUnavailable::NoProducts;
}

std::string_view ephemerisUnavailableName(EphemerisUnavailable reason) {
  switch (reason) {
    case EphemerisUnavailable::NoProducts: return "no products";
    case EphemerisUnavailable::SatelliteNotInProducts: return "satellite not in products";
    case EphemerisUnavailable::OutsideSpan: return "outside product span";
    case EphemerisUnavailable::Gap: return "gap";
    case EphemerisUnavailable::BadValueMarker: return "bad value marker";
    case EphemerisUnavailable::NotEnoughNodes: return "not enough nodes";
    case EphemerisUnavailable::NoValidRecord: return "no valid record";
    case EphemerisUnavailable::SystemNotModelled: return "system not modelled";
  }
  return "?";
}

namespace {

/// The span edge within PreciseEphemeris::kMaxEdgeExtension_s of a time outside the span, if any.
std::optional<GnssTime> nearEdge(const std::optional<ProductSpan>& span, const GnssTime& t) {
  if (!span) return std::nullopt;
  if (t < span->first && span->first - t < PreciseEphemeris::kMaxEdgeExtension_s) return span->first;
  if (span->last < t && t - span->last < PreciseEphemeris::kMaxEdgeExtension_s) return span->last;
  return std::nullopt;
}

}  // namespace

EphemerisAnswer<EphemerisClock> PreciseEphemeris::satelliteClock(const SatelliteId& sat, const GnssTime& t) const {
  using A = EphemerisAnswer<EphemerisClock>;
  const auto c = clock(sat, t);
  if (c.ok()) return A::success({c.value->clock_bias_s, c.value->clock_drift_s_per_s, std::nullopt});
  // Edge: extend linearly with the slope of the first/last interval.
  if (c.status == ProductStatus::OutsideSpan) {
    if (const auto edge = nearEdge(clockSpan(), t)) {
      const auto r = clock(sat, *edge);
      if (r.ok() && r.value->clock_drift_s_per_s) {
        const double bias_s = r.value->clock_bias_s + *r.value->clock_drift_s_per_s * (t - *edge);
        return A::success({bias_s, r.value->clock_drift_s_per_s, std::nullopt});
      }
    }
  }
  return A::unavailable(ephemerisUnavailable(c.status), c.reason);
}

EphemerisAnswer<EphemerisOrbit> PreciseEphemeris::satelliteOrbit(const SatelliteId& sat, const GnssTime& t) const {
  using A = EphemerisAnswer<EphemerisOrbit>;
  const auto o = orbit(sat, t);
  if (o.ok()) {
    return A::success({o.value->position_ecef_m, o.value->velocity_ecef_mps, EphemerisReference::CentreOfMass,
                       std::nullopt});
  }
  // Edge: a second-order step from the edge (central gravity only).
  if (o.status == ProductStatus::OutsideSpan) {
    if (const auto edge = nearEdge(orbitSpan(), t)) {
      const auto r = orbit(sat, *edge);
      if (r.ok()) {
        const double dt = t - *edge;
        const Eigen::Vector3d& p = r.value->position_ecef_m;
        const Eigen::Vector3d a = -kGmEarthIers_m3ps2 / std::pow(p.norm(), 3) * p;
        return A::success({p + r.value->velocity_ecef_mps * dt + 0.5 * a * dt * dt,
                           r.value->velocity_ecef_mps + a * dt, EphemerisReference::CentreOfMass, std::nullopt});
      }
    }
  }
  return A::unavailable(ephemerisUnavailable(o.status), o.reason);
}

PreciseEphemeris::PreciseEphemeris(PreciseEphemerisOptions options) : options_(options) {
  options_.interpolation_points =
      std::max(2, std::min(options_.interpolation_points, static_cast<int>(kMaxWindowNodes)));
}

void PreciseEphemeris::addOrbits(const Sp3File& file) {
  if (file.epochs.empty()) return;
  if (file.header.interval_s > 0.0 &&
      (orbit_interval_s_ <= 0.0 || file.header.interval_s < orbit_interval_s_)) {
    orbit_interval_s_ = file.header.interval_s;
  }
  extendSpan(orbit_span_, file.epochs.front(), file.epochs.back());
  for (const auto& [sat, records] : file.satellites) {
    std::vector<OrbitNode> nodes;
    nodes.reserve(records.size());
    for (const Sp3Record& r : records) {
      nodes.push_back({r.time, r.position_ecef_m, r.velocity_ecef_mps});
    }
    mergeSeries<OrbitNode>(orbits_[sat], nodes, merge_report_,
                           [](const OrbitNode& n) { return n.position_ecef_m.has_value(); });
    std::vector<ClockNode> clock_nodes;
    clock_nodes.reserve(records.size());
    for (const Sp3Record& r : records) clock_nodes.push_back({r.time, r.clock_bias_s, r.clock_marked_bad});
    ParseReport ignored;  // the overlap is already counted for the orbit nodes
    mergeSeries<ClockNode>(sp3_clocks_[sat], clock_nodes, ignored,
                           [](const ClockNode& n) { return n.clock_bias_s.has_value(); });
  }
}

void PreciseEphemeris::addClocks(const RinexClockFile& file) {
  for (const auto& [sat, records] : file.satellite_clocks) {
    if (records.empty()) continue;
    std::vector<ClockNode> nodes;
    nodes.reserve(records.size());
    std::vector<GnssTime> times;
    times.reserve(records.size());
    for (const ClockRecord& r : records) {
      nodes.push_back({r.time, r.clock_bias_s, false});
      times.push_back(r.time);
    }
    extendSpan(clock_span_, records.front().time, records.back().time);
    const double spacing = modalSpacing_s(times);
    if (spacing > 0.0 && (clock_interval_s_ <= 0.0 || spacing < clock_interval_s_)) clock_interval_s_ = spacing;
    mergeSeries<ClockNode>(clocks_[sat], nodes, merge_report_,
                           [](const ClockNode& n) { return n.clock_bias_s.has_value(); });
  }
}

PreciseEphemeris PreciseEphemeris::load(const std::vector<std::string>& sp3_paths,
                                        const std::vector<std::string>& clock_paths,
                                        PreciseEphemerisOptions options) {
  return load(sp3_paths, clock_paths, RecordFilter{}, options);
}

PreciseEphemeris PreciseEphemeris::load(const std::vector<std::string>& sp3_paths,
                                        const std::vector<std::string>& clock_paths, const RecordFilter& filter,
                                        PreciseEphemerisOptions options) {
  PreciseEphemeris eph(options);
  Sp3ReadOptions sp3_options;
  sp3_options.filter = filter;
  sp3_options.margin_epochs = std::max(2, options.interpolation_points) + 2;
  RinexClockReadOptions clock_options{false, filter};
  if (filter.first) clock_options.filter.first = *filter.first - kClockWindowMargin_s;
  if (filter.last) clock_options.filter.last = *filter.last + kClockWindowMargin_s;
  // A file's reading problems and the single bad values the sanity checks find
  // (product_sanity.h: marked bad, never used) are the products' problems.
  const auto readingProblems = [&eph](const std::string& path, const ParseReport& report) {
    if (!report.clean()) eph.merge_report_.addProblem(0, report.headline(path));
  };
  // A file that holds nothing for the observations is a wrong input (another day,
  // another system), never silently replaced by another source.
  const auto window = [&filter](const RecordFilter& f) {
    std::string text = "of " + std::string(filter.systems.empty() ? "any system" : "the processed systems");
    if (f.first && f.last) text += " between " + timeText(*f.first) + " and " + timeText(*f.last);
    return text;
  };
  for (const auto& p : sp3_paths) {
    Sp3File f = readSp3(p, sp3_options);
    if (filter.active() && f.satellites.empty())
      throw ParseError(p, 0, "no orbit record " + window(sp3_options.filter) +
                                " (the observation window): products of another "
                                 "day or system?");
    readingProblems(p, f.report);
    const std::vector<OrbitOutlier> outliers = options.check_products ? findOrbitOutliers(f) : std::vector<OrbitOutlier>{};
    for (const auto& o : outliers) eph.merge_report_.addProblem(0, p + ": " + o.describe() + "; not used");
    markOrbitOutliers(f, outliers);
    eph.addOrbits(f);
  }
  for (const auto& p : clock_paths) {
    RinexClockFile f = readRinexClock(p, clock_options);
    if (filter.active() && f.satellite_clocks.empty())
      throw ParseError(p, 0, "no satellite clock record " + window(clock_options.filter) +
                                 " (the observation window with a 2-h margin): a clock file of another day or "
                                 "system? (it would otherwise fall back to the SP3 clocks)");
    readingProblems(p, f.report);
    const std::vector<ClockOutlier> outliers = options.check_products ? findClockOutliers(f) : std::vector<ClockOutlier>{};
    for (const auto& o : outliers) eph.merge_report_.addProblem(0, p + ": " + o.describe() + "; not used");
    markClockOutliers(f, outliers);
    eph.addClocks(f);
  }
  return eph;
}

double PreciseEphemeris::maxNodeSpacing_s() const {
  if (options_.max_node_spacing_s > 0.0) return options_.max_node_spacing_s;
  return 1.5 * orbit_interval_s_;
}

double PreciseEphemeris::maxClockSpacing_s() const {
  if (options_.max_clock_spacing_s > 0.0) return options_.max_clock_spacing_s;
  return 1.5 * (clocks_.empty() ? orbit_interval_s_ : clock_interval_s_);
}

std::optional<ProductSpan> PreciseEphemeris::orbitSpan() const { return orbit_span_; }
std::optional<ProductSpan> PreciseEphemeris::clockSpan() const { return spanOfClockSource(); }
std::optional<ProductSpan> PreciseEphemeris::spanOfClockSource() const {
  return clocks_.empty() ? orbit_span_ : clock_span_;
}

std::set<SatelliteId> PreciseEphemeris::orbitSatellites() const {
  std::set<SatelliteId> out;
  for (const auto& [sat, nodes] : orbits_) out.insert(sat);
  return out;
}

std::set<SatelliteId> PreciseEphemeris::clockSatellites() const {
  std::set<SatelliteId> out;
  if (!clocks_.empty()) {
    for (const auto& [sat, nodes] : clocks_) out.insert(sat);
  } else {
    for (const auto& [sat, nodes] : sp3_clocks_) {
      if (std::any_of(nodes.begin(), nodes.end(), [](const ClockNode& n) { return n.clock_bias_s.has_value(); })) {
        out.insert(sat);
      }
    }
  }
  return out;
}

// ------------------------------------------------------------------ orbit
namespace {

/// Up to kMaxWindowNodes node indices, without allocation.
class NodeIndices {
 public:
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void push_back(std::size_t i) { index_[size_++] = i; }
  std::size_t operator[](std::size_t k) const { return index_[k]; }
  std::size_t back() const { return index_[size_ - 1]; }
  std::size_t front() const { return index_[0]; }

 private:
  std::size_t index_[kMaxWindowNodes];
  std::size_t size_ = 0;
};

/// Why a walk along the nodes stopped.
struct WalkStop {
  enum Kind { Enough, DataEdge, Break } kind = Enough;
  ProductStatus status = ProductStatus::Ok;
  std::string reason;
};

using OrbitResult = ProductResult<SatelliteOrbit>;

template <class OrbitNode>  // PreciseEphemeris::OrbitNode
OrbitResult badMarker(const OrbitNode& n, const SatelliteId& sat) {
  return OrbitResult::failure(ProductStatus::BadValueMarker,
                              "bad value marker in SP3 at " + timeText(n.time) + " for " + sat.toString());
}

/// The failure when the nodes that bracket t (k: the first node after t) are missing,
/// invalid or too far apart; nullopt when they serve.
template <class OrbitNode>  // PreciseEphemeris::OrbitNode
std::optional<OrbitResult> bracketProblem(const std::vector<OrbitNode>& nodes, std::size_t k, bool exact,
                                          const GnssTime& t, double max_gap, const SatelliteId& sat) {
  if (exact) {
    if (!nodes[k - 1].position_ecef_m) return badMarker(nodes[k - 1], sat);
    return std::nullopt;
  }
  if (k == 0 || k == nodes.size()) {
    const OrbitNode& nearest = k == 0 ? nodes.front() : nodes.back();
    return OrbitResult::failure(ProductStatus::Gap, "gap: nearest SP3 node for " + sat.toString() + " is " +
                                                        minutesText(std::abs(nearest.time - t)) + " away (" +
                                                        (k == 0 ? "none before " : "none after ") + timeText(t) +
                                                        ", max allowed spacing " + minutesText(max_gap) + ")");
  }
  const OrbitNode& l = nodes[k - 1];
  const OrbitNode& r = nodes[k];
  if (!l.position_ecef_m) return badMarker(l, sat);
  if (!r.position_ecef_m) return badMarker(r, sat);
  if (r.time - l.time > max_gap) {
    return OrbitResult::failure(ProductStatus::Gap, "gap: nearest SP3 node for " + sat.toString() + " is " +
                                                        minutesText(std::min(t - l.time, r.time - t)) + " away (nodes " +
                                                        timeText(l.time) + " and " + timeText(r.time) + " are " +
                                                        minutesText(r.time - l.time) + " apart, max allowed " +
                                                        minutesText(max_gap) + ")");
  }
  return std::nullopt;
}

/// Walks from `start` by `step` (+1 or -1), collecting up to n_points consecutive
/// usable nodes into `out`; says why it stopped.
template <class OrbitNode>  // PreciseEphemeris::OrbitNode
WalkStop walkNodes(const std::vector<OrbitNode>& nodes, std::size_t start, int step, std::size_t n_points,
                   double max_gap, NodeIndices& out) {
  WalkStop stop;
  std::size_t i = start;
  for (;;) {
    if (out.size() >= n_points) return stop;
    if ((step < 0 && i == static_cast<std::size_t>(-1)) || (step > 0 && i >= nodes.size())) {
      stop.kind = WalkStop::DataEdge;
      return stop;
    }
    const OrbitNode& n = nodes[i];
    if (!n.position_ecef_m) {
      stop = {WalkStop::Break, ProductStatus::BadValueMarker, "bad value marker in SP3 at " + timeText(n.time)};
      return stop;
    }
    if (!out.empty() && std::abs(n.time - nodes[out.back()].time) > max_gap) {
      stop = {WalkStop::Break, ProductStatus::Gap,
              "gap: SP3 nodes " + timeText(std::min(n.time, nodes[out.back()].time)) + " and " +
                  timeText(std::max(n.time, nodes[out.back()].time)) + " are " +
                  minutesText(std::abs(n.time - nodes[out.back()].time)) + " apart (max allowed " +
                  minutesText(max_gap) + ")"};
      return stop;
    }
    out.push_back(i);
    i = step < 0 ? i - 1 : i + 1;
  }
}

/// The nodes collected on each side of t and why each walk stopped.
struct NodeWalks {
  NodeIndices left, right;  // left: at or before t (nearest first); right: after t
  WalkStop left_stop, right_stop;
};

/// The centred window of n_points nodes, shifted inward at data edges (and at gaps
/// if allowed); the failure when it cannot be had (nullopt: `window` is set).
std::optional<OrbitResult> centredWindow(const NodeWalks& walks, std::size_t n_points, bool shift_at_gaps,
                                         const SatelliteId& sat, const GnssTime& t, NodeIndices& window) {
  const NodeIndices& left = walks.left;
  const NodeIndices& right = walks.right;
  std::size_t want_left = n_points / 2, want_right = n_points - want_left;
  const auto can_shift = [&](const WalkStop& s) {
    return s.kind == WalkStop::DataEdge || (s.kind == WalkStop::Break && shift_at_gaps);
  };
  const auto refuse = [&](const WalkStop& s) {
    return OrbitResult::failure(s.status, s.reason + ": the " + std::to_string(n_points) + "-node window for " +
                                              sat.toString() + " at " + timeText(t) + " would straddle it");
  };
  if (left.size() < want_left) {
    if (!can_shift(walks.left_stop)) return refuse(walks.left_stop);
    want_right += want_left - left.size();
    want_left = left.size();
  }
  if (right.size() < want_right) {
    if (!can_shift(walks.right_stop)) return refuse(walks.right_stop);
    want_left += want_right - right.size();
    want_right = right.size();
  }
  if (left.size() < want_left) {
    if (walks.left_stop.kind == WalkStop::Break) return refuse(walks.left_stop);
    return OrbitResult::failure(ProductStatus::NotEnoughNodes,
                                "only " + std::to_string(left.size() + right.size()) + " usable SP3 nodes for " +
                                    sat.toString() + " around " + timeText(t) + " (need " +
                                    std::to_string(n_points) + ")");
  }
  for (std::size_t i = want_left; i-- > 0;) window.push_back(left[i]);
  for (std::size_t i = 0; i < want_right; ++i) window.push_back(right[i]);
  return std::nullopt;
}

/// The interpolation terms of a window kept between queries (the fields of
/// PreciseEphemeris::OrbitQueryScratch, which only PreciseEphemeris names).
struct WindowTerms {
  GnssTime& t;
  double& h;
  std::size_t& size;  // 0: nothing kept
  GnssTime* node_times;
  double* w;
  double* dw;
  double* cos;
  double* sin;
};

/// Lagrange weights in a scaled time relative to the window centre, and the Earth
/// rotations from the nodes to t; kept when the previous query had the same node
/// times at the same query time.
template <class OrbitNode>  // PreciseEphemeris::OrbitNode
void updateWindowTerms(const WindowTerms& terms, const std::vector<OrbitNode>& nodes, const NodeIndices& window,
                       const GnssTime& t, double h) {
  const bool same_window = terms.size == window.size() && terms.t == t && terms.h == h && [&] {
    for (std::size_t j = 0; j < window.size(); ++j)
      if (!(terms.node_times[j] == nodes[window[j]].time)) return false;
    return true;
  }();
  if (same_window) return;
  const GnssTime centre = nodes[window[window.size() / 2]].time;
  const std::size_t m = window.size();
  double tau[kMaxWindowNodes];
  for (std::size_t j = 0; j < m; ++j) tau[j] = (nodes[window[j]].time - centre) / h;
  terms.size = m;
  lagrangeWeights(tau, m, (t - centre) / h, terms.w, terms.dw);
  for (std::size_t j = 0; j < m; ++j) {
    terms.node_times[j] = nodes[window[j]].time;
    const double th = kEarthRotationRate_radps * (nodes[window[j]].time - t);
    terms.cos[j] = std::cos(th);
    terms.sin[j] = std::sin(th);
  }
  terms.t = t;
  terms.h = h;
}

/// Position and velocity at t from the window's nodes and terms.
template <class OrbitNode>  // PreciseEphemeris::OrbitNode
SatelliteOrbit interpolateWindow(const std::vector<OrbitNode>& nodes, const NodeIndices& window,
                                 const WindowTerms& terms, double h, const PreciseEphemerisOptions& options) {
  const bool inertial = options.interpolate_in_inertial_frame;
  bool have_velocities = options.use_sp3_velocity;
  Eigen::Vector3d pos = Eigen::Vector3d::Zero(), dpos = Eigen::Vector3d::Zero(), vel = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < window.size(); ++j) {
    const OrbitNode& n = nodes[window[j]];
    const double c = terms.cos[j], s = terms.sin[j];  // rotateToQueryFrame's, dt = node - t
    const Eigen::Vector3d p = inertial ? rotateAboutZ(*n.position_ecef_m, c, s) : *n.position_ecef_m;
    pos += terms.w[j] * p;
    dpos += terms.dw[j] * p;
    if (have_velocities && n.velocity_ecef_mps) {
      const Eigen::Vector3d v =
          inertial ? rotateAboutZ(*n.velocity_ecef_mps + earthRotationCross(*n.position_ecef_m), c, s)
                   : *n.velocity_ecef_mps;
      vel += terms.w[j] * v;
    } else {
      have_velocities = false;
    }
  }
  SatelliteOrbit out;
  out.position_ecef_m = pos;  // the query frame coincides with ECEF at t
  if (have_velocities) {
    out.velocity_ecef_mps = inertial ? Eigen::Vector3d(vel - earthRotationCross(pos)) : vel;
    out.velocity_source = VelocitySource::Sp3VelocityRecords;
  } else {
    const Eigen::Vector3d v = dpos / h;
    out.velocity_ecef_mps = inertial ? Eigen::Vector3d(v - earthRotationCross(pos)) : v;
    out.velocity_source = VelocitySource::PositionInterpolant;
  }
  out.window_first = nodes[window.front()].time;
  out.window_last = nodes[window.back()].time;
  out.nodes_used = static_cast<int>(window.size());
  return out;
}

}  // namespace

ProductResult<SatelliteOrbit> PreciseEphemeris::orbit(const SatelliteId& sat, const GnssTime& t) const {
  OrbitQueryScratch scratch;
  return orbit(sat, t, scratch);
}

ProductResult<SatelliteOrbit> PreciseEphemeris::orbit(const SatelliteId& sat, const GnssTime& t,
                                                      OrbitQueryScratch& scratch) const {
  using R = ProductResult<SatelliteOrbit>;
  if (orbits_.empty() || !orbit_span_) return R::failure(ProductStatus::NoProducts, "no SP3 orbit loaded");
  const auto it = orbits_.find(sat);
  if (it == orbits_.end()) {
    return R::failure(ProductStatus::SatelliteNotInProducts, "satellite " + sat.toString() + " not in products (SP3)");
  }
  if (t < orbit_span_->first || t > orbit_span_->last) {
    return R::failure(ProductStatus::OutsideSpan, "unavailable: time " + timeText(t) + " outside product span [" +
                                                      timeText(orbit_span_->first) + ", " +
                                                      timeText(orbit_span_->last) + "]");
  }
  const std::vector<OrbitNode>& nodes = it->second;
  const std::size_t n_points = static_cast<std::size_t>(options_.interpolation_points);
  const double max_gap = maxNodeSpacing_s();
  const auto by_time = [](const GnssTime& a, const OrbitNode& b) { return a < b.time; };
  // k: first node strictly after t; nodes[k-1] is at or before t.
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(nodes.begin(), nodes.end(), t, by_time) - nodes.begin());
  const bool exact = k > 0 && nodes[k - 1].time == t;

  // 1. The nodes that bracket t must exist, be valid and be close enough.
  if (auto problem = bracketProblem(nodes, k, exact, t, max_gap, sat)) return std::move(*problem);

  // 1b. Streams: cubic Hermite between the bracketing nodes when both have a velocity.
  if (options_.hermite_between_velocity_nodes) {
    const OrbitNode& l = nodes[k - 1];
    const OrbitNode& r = exact ? l : nodes[k];
    if (auto o = hermite(l, r, t, options_.interpolate_in_inertial_frame)) return R::success(*o);
  }

  // 2. Walk outward collecting up to n_points consecutive usable nodes per side
  //    (indices into `nodes`, in fixed-size buffers: no allocation per query).
  NodeWalks walks;
  walks.left_stop = walkNodes(nodes, k - 1, -1, n_points, max_gap, walks.left);
  walks.right_stop = walkNodes(nodes, k, +1, n_points, max_gap, walks.right);

  // 3. Centred window, shifted inward at data edges (and at gaps if allowed).
  NodeIndices window;
  if (auto problem = centredWindow(walks, n_points, options_.shift_window_at_gaps, sat, t, window))
    return std::move(*problem);

  // 4. Lagrange interpolation in a scaled time relative to the window centre (weights
  //    and rotations shared with the previous query through `scratch` when its window
  //    had the same node times at the same query time).
  const double h = orbit_interval_s_ > 0.0 ? orbit_interval_s_ : 1.0;
  static_assert(kMaxWindowNodes <= OrbitQueryScratch::kCapacity, "scratch too small for a window");
  const WindowTerms terms{scratch.t_,          scratch.h_,         scratch.size_,       scratch.node_times_.data(),
                          scratch.w_.data(),   scratch.dw_.data(), scratch.cos_.data(), scratch.sin_.data()};
  updateWindowTerms(terms, nodes, window, t, h);
  return R::success(interpolateWindow(nodes, window, terms, h, options_));
}

template <class Node>
std::optional<SatelliteOrbit> PreciseEphemeris::hermite(const Node& l, const Node& r, const GnssTime& t,
                                                        bool inertial) {
  if (!l.velocity_ecef_mps || !r.velocity_ecef_mps || !l.position_ecef_m || !r.position_ecef_m) return std::nullopt;
  SatelliteOrbit out;
  out.velocity_source = VelocitySource::Sp3VelocityRecords;
  out.window_first = l.time;
  out.window_last = r.time;
  out.nodes_used = l.time == r.time ? 1 : 2;
  if (l.time == r.time) {  // exactly on a node: the node's values
    out.position_ecef_m = *l.position_ecef_m;
    out.velocity_ecef_mps = *l.velocity_ecef_mps;
    return out;
  }
  // Node states in the non-rotating frame aligned with ECEF at t (velocity: v + omega x r).
  const auto state = [&](const Node& n, Eigen::Vector3d& p, Eigen::Vector3d& v) {
    const double dt = n.time - t;
    p = inertial ? rotateToQueryFrame(*n.position_ecef_m, dt) : *n.position_ecef_m;
    v = inertial ? rotateToQueryFrame(*n.velocity_ecef_mps + earthRotationCross(*n.position_ecef_m), dt)
                 : *n.velocity_ecef_mps;
  };
  Eigen::Vector3d p0, v0, p1, v1;
  state(l, p0, v0);
  state(r, p1, v1);
  const double h = r.time - l.time, s = (t - l.time) / h, s2 = s * s, s3 = s2 * s;
  const Eigen::Vector3d pos = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * v0 + (-2 * s3 + 3 * s2) * p1 +
                              (s3 - s2) * h * v1;
  const Eigen::Vector3d vel = ((6 * s2 - 6 * s) * p0 + (-6 * s2 + 6 * s) * p1) / h + (3 * s2 - 4 * s + 1) * v0 +
                              (3 * s2 - 2 * s) * v1;
  out.position_ecef_m = pos;
  out.velocity_ecef_mps = inertial ? Eigen::Vector3d(vel - earthRotationCross(pos)) : vel;
  return out;
}

// ------------------------------------------------------------------ clock
ProductResult<SatelliteClock> PreciseEphemeris::clock(const SatelliteId& sat, const GnssTime& t) const {
  using R = ProductResult<SatelliteClock>;
  if (!clocks_.empty()) {
    const auto it = clocks_.find(sat);
    if (it == clocks_.end()) {
      return R::failure(ProductStatus::SatelliteNotInProducts,
                        "satellite " + sat.toString() + " not in products (RINEX clock)");
    }
    return interpolateClock(it->second, sat, t, ClockSource::RinexClock);
  }
  if (orbits_.empty()) return R::failure(ProductStatus::NoProducts, "no clock product loaded (neither CLK nor SP3)");
  const auto it = orbits_.find(sat);
  if (it == orbits_.end()) {
    return R::failure(ProductStatus::SatelliteNotInProducts, "satellite " + sat.toString() + " not in products (SP3)");
  }
  return interpolateClock(sp3_clocks_.at(sat), sat, t, ClockSource::Sp3);
}

ProductResult<SatelliteClock> PreciseEphemeris::interpolateClock(const std::vector<ClockNode>& series,
                                                                 const SatelliteId& sat, const GnssTime& t,
                                                                 ClockSource source) const {
  using R = ProductResult<SatelliteClock>;
  // Texts for the reasons only: no string is built on success.
  const auto src = [source] { return std::string(source == ClockSource::RinexClock ? "clock file" : "SP3 clock"); };
  const auto span = spanOfClockSource();
  if (!span || t < span->first || t > span->last) {
    return R::failure(ProductStatus::OutsideSpan,
                      "unavailable: time " + timeText(t) + " outside " + src() + " span" +
                          (span ? " [" + timeText(span->first) + ", " + timeText(span->last) + "]" : ""));
  }
  const auto name = [&sat] { return sat.toString(); };
  const double max_gap = maxClockSpacing_s();
  const auto unusable = [&](const ClockNode& n) {
    return R::failure(n.marked_bad ? ProductStatus::BadValueMarker : ProductStatus::Gap,
                      (n.marked_bad ? "bad value marker in " : "no value in ") + src() + " at " + timeText(n.time) +
                          " for " + name());
  };
  const auto by_time = [](const GnssTime& a, const ClockNode& b) { return a < b.time; };
  const std::size_t k =
      static_cast<std::size_t>(std::upper_bound(series.begin(), series.end(), t, by_time) - series.begin());
  SatelliteClock out;
  out.source = source;
  if (k > 0 && series[k - 1].time == t) {
    const ClockNode& n = series[k - 1];
    if (!n.clock_bias_s) return unusable(n);
    out.clock_bias_s = *n.clock_bias_s;  // exactly the file's value
    out.exact_record = true;
    const ClockNode* other = k < series.size() ? &series[k] : (k >= 2 ? &series[k - 2] : nullptr);
    if (other && other->clock_bias_s && std::abs(other->time - n.time) <= max_gap) {
      out.clock_drift_s_per_s = (*other->clock_bias_s - *n.clock_bias_s) / (other->time - n.time);
    }
    return R::success(out);
  }
  if (k == 0 || k == series.size()) {
    const ClockNode& nearest = k == 0 ? series.front() : series.back();
    return R::failure(ProductStatus::Gap, "gap: nearest " + src() + " record for " + name() + " is " +
                                              secondsText(std::abs(nearest.time - t)) + " away (none " +
                                              (k == 0 ? "before " : "after ") + timeText(t) + ")");
  }
  const ClockNode& l = series[k - 1];
  const ClockNode& r = series[k];
  if (!l.clock_bias_s) return unusable(l);
  if (!r.clock_bias_s) return unusable(r);
  const double span_s = r.time - l.time;
  if (span_s > max_gap) {
    return R::failure(ProductStatus::Gap, "gap: " + src() + " records for " + name() + " at " + timeText(l.time) +
                                              " and " + timeText(r.time) + " are " + secondsText(span_s) +
                                              " apart (max allowed " + secondsText(max_gap) + ")");
  }
  const double wr = (t - l.time) / span_s;
  out.clock_bias_s = (1.0 - wr) * *l.clock_bias_s + wr * *r.clock_bias_s;
  out.clock_drift_s_per_s = (*r.clock_bias_s - *l.clock_bias_s) / span_s;
  return R::success(out);
}

// ------------------------------------------------------------------ coverage
ProductCoverage checkCoverage(const PreciseEphemeris& products, const GnssTime& first, const GnssTime& last,
                              double interval_s, const std::set<SatelliteId>& needed) {
  ProductCoverage cov;
  cov.first = first;
  cov.last = last;
  cov.orbit_span = products.orbitSpan();
  cov.clock_span = products.clockSpan();
  cov.orbit_span_covers = cov.orbit_span && cov.orbit_span->first <= first && cov.orbit_span->last >= last;
  cov.clock_span_covers = cov.clock_span && cov.clock_span->first <= first && cov.clock_span->last >= last;
  const auto orbit_sats = products.orbitSatellites();
  const auto clock_sats = products.clockSatellites();
  for (const auto& sat : needed) {
    if (!orbit_sats.count(sat)) cov.missing_orbit.insert(sat);
    if (!clock_sats.count(sat)) cov.missing_clock.insert(sat);
  }
  constexpr std::size_t kMaxEpochs = 100000;
  const double span = last - first;
  std::vector<GnssTime> epochs;
  if (span >= 0.0) {
    if (interval_s > 0.0) {
      const auto n = static_cast<std::size_t>(std::min(std::floor(span / interval_s), double(kMaxEpochs - 1)));
      for (std::size_t i = 0; i <= n; ++i) epochs.push_back(first + static_cast<double>(i) * interval_s);
    } else {
      epochs.push_back(first);
    }
    if (epochs.back() != last && epochs.size() < kMaxEpochs) epochs.push_back(last);
  }
  cov.epochs_checked = epochs.size();
  const auto note = [](auto& map, const SatelliteId& sat, const std::string& reason) {
    auto& entry = map[sat];
    if (entry.first++ == 0) entry.second = reason;
  };
  for (const auto& sat : needed) {
    const bool has_orbit = !cov.missing_orbit.count(sat), has_clock = !cov.missing_clock.count(sat);
    for (const GnssTime& t : epochs) {
      if (has_orbit) {
        const auto o = products.orbit(sat, t);
        if (!o.ok()) note(cov.orbit_gaps, sat, o.reason);
      }
      if (has_clock) {
        const auto c = products.clock(sat, t);
        if (!c.ok()) note(cov.clock_gaps, sat, c.reason);
      }
    }
  }
  return cov;
}

std::vector<std::string> ProductCoverage::describe() const {
  std::vector<std::string> out;
  const auto spanText = [](const std::optional<ProductSpan>& s) {
    return s ? "[" + timeText(s->first) + ", " + timeText(s->last) + "]" : std::string("none");
  };
  out.push_back("requested " + timeText(first) + " .. " + timeText(last) + " (" + std::to_string(epochs_checked) +
                " epochs checked)");
  out.push_back(std::string("orbit span ") + spanText(orbit_span) + (orbit_span_covers ? " covers it" : " does NOT cover it"));
  out.push_back(std::string("clock span ") + spanText(clock_span) + (clock_span_covers ? " covers it" : " does NOT cover it"));
  const auto list = [](const std::set<SatelliteId>& s) {
    std::string text;
    for (const auto& sat : s) text += (text.empty() ? "" : " ") + sat.toString();
    return text;
  };
  if (!missing_orbit.empty()) out.push_back("no orbit for: " + list(missing_orbit));
  if (!missing_clock.empty()) out.push_back("no clock for: " + list(missing_clock));
  for (const auto& [sat, e] : orbit_gaps) {
    out.push_back("orbit " + sat.toString() + " unavailable at " + std::to_string(e.first) + " epochs, first: " + e.second);
  }
  for (const auto& [sat, e] : clock_gaps) {
    out.push_back("clock " + sat.toString() + " unavailable at " + std::to_string(e.first) + " epochs, first: " + e.second);
  }
  if (complete()) out.push_back("products complete for the requested satellites and span");
  return out;
}

}  // namespace ppp
