#include "ppp_bayes_tree/ppp/pipeline/broadcast_single_point.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "ppp_bayes_tree/models/troposphere.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"

namespace ppp {
namespace {

struct Candidate {
  SatelliteId satellite;
  double code_if_m = 0.0;
  Eigen::Vector3d position_ecef_m;  // at transmission, Earth-fixed at transmission
  double clock_m = 0.0;             // satellite clock of the IF pair [m]
  int system_column = 0;
};

/// The code pair of a system for the single-point solution, best first, and the
/// receiver clock it shares (QZSS: GPS time). GPS/QZSS L1 C/A with L2C, L2 P(Y) or
/// L5; Galileo E1 with E5a or E5b.
struct SinglePointRow {
  GnssSystem system;
  GnssSystem clock_system;
  std::vector<const char*> code1, code2;
};
const SinglePointRow kSinglePointRows[] = {
    {GnssSystem::GPS, GnssSystem::GPS, {"C1C"}, {"C2L", "C2S", "C2X", "C2W", "C5Q", "C5I", "C5X"}},
    {GnssSystem::QZSS, GnssSystem::GPS, {"C1C"}, {"C2L", "C2S", "C2X", "C2W", "C5Q", "C5I", "C5X"}},
    {GnssSystem::Galileo, GnssSystem::Galileo, {"C1C", "C1B", "C1X"}, {"C5Q", "C5I", "C5X", "C7Q", "C7I", "C7X"}},
};

const SinglePointRow* singlePointRow(GnssSystem system) {
  for (const auto& row : kSinglePointRows)
    if (row.system == system) return &row;
  return nullptr;
}

const Observation* firstPresent(const ObsEpoch& epoch, const SatelliteId& sat, const std::vector<const char*>& codes) {
  for (const char* text : codes) {
    const auto code = ObservationCode::parse(text);
    const Observation* o = code ? epoch.find(sat, *code) : nullptr;
    if (o && o->value && std::isfinite(*o->value) && *o->value > 1e6) return o;
  }
  return nullptr;
}

const Observation* phaseOf(const ObsEpoch& epoch, const SatelliteId& sat, const Observation* code) {
  if (!code) return nullptr;
  const Observation* o =
      epoch.find(sat, ObservationCode{ObservableType::CarrierPhase, code->code.band, code->code.attribute});
  return o && o->value && std::isfinite(*o->value) ? o : nullptr;
}

}  // namespace

double IonosphereFreePair::code_m() const {
  const double a = f1_hz * f1_hz, b = f2_hz * f2_hz;
  return (a * *code1->value - b * *code2->value) / (a - b);
}

std::optional<double> IonosphereFreePair::phase_m() const {
  if (!phase1 || !phase2) return std::nullopt;
  const double a = f1_hz * f1_hz, b = f2_hz * f2_hz;
  const double l1 = *phase1->value * kSpeedOfLight_mps / f1_hz, l2 = *phase2->value * kSpeedOfLight_mps / f2_hz;
  return (a * l1 - b * l2) / (a - b);
}

IonosphereFreePair ionosphereFreePair(const ObsEpoch& epoch, const SatelliteId& sat) {
  IonosphereFreePair pair;
  const SinglePointRow* row = singlePointRow(sat.system);
  if (row == nullptr) return pair;
  const Observation* p1 = firstPresent(epoch, sat, row->code1);
  const Observation* p2 = firstPresent(epoch, sat, row->code2);
  if (!p1 || !p2) return pair;
  const auto f1 = carrierFrequency_hz(sat.system, p1->code.band);
  const auto f2 = carrierFrequency_hz(sat.system, p2->code.band);
  if (!f1 || !f2) return pair;
  pair.code1 = p1;
  pair.code2 = p2;
  pair.f1_hz = *f1;
  pair.f2_hz = *f2;
  pair.phase1 = phaseOf(epoch, sat, p1);
  pair.phase2 = phaseOf(epoch, sat, p2);
  return pair;
}

std::map<SatelliteId, double> IonosphereFreeCodeSmoother::update(const ObsEpoch& epoch) {
  std::map<SatelliteId, double> out;
  for (const auto& entry : epoch.satellites) {
    const SatelliteId sat = entry.satellite;
    const IonosphereFreePair pair = ionosphereFreePair(epoch, sat);
    if (!pair.hasCode()) {
      arcs_.erase(sat);
      continue;
    }
    const double code = pair.code_m();
    const auto phase = pair.phase_m();
    const bool slip = (pair.phase1 && (pair.phase1->lli.value_or(0) & 1)) ||
                      (pair.phase2 && (pair.phase2->lli.value_or(0) & 1));
    auto it = arcs_.find(sat);
    const bool continues = it != arcs_.end() && phase && !slip && epoch.time - it->second.last <= max_gap_s_ &&
                           epoch.time > it->second.last;
    if (!continues) {
      if (phase) {
        arcs_[sat] = Arc{epoch.time, code, *phase, 1};
      } else {
        arcs_.erase(sat);
      }
      out[sat] = code;
      continue;
    }
    Arc& arc = it->second;
    arc.epochs = std::min(arc.epochs + 1, window_);
    const double k = arc.epochs;
    arc.smoothed_m = code / k + (k - 1.0) / k * (arc.smoothed_m + (*phase - arc.phase_m));
    arc.phase_m = *phase;
    arc.last = epoch.time;
    out[sat] = arc.smoothed_m;
  }
  return out;
}

namespace {

/// The candidate of one satellite: its ionosphere-free code (smoothed when given) and
/// its broadcast position and clock at transmission; nullopt without them.
std::optional<Candidate> candidateOf(const ObsEpoch& epoch, const SatelliteId& sat,
                                     const BroadcastEphemerisStore& ephemerides,
                                     const std::map<SatelliteId, double>* smoothed_codes) {
  const IonosphereFreePair pair = ionosphereFreePair(epoch, sat);
  if (!pair.hasCode()) return std::nullopt;
  const Observation* p1 = pair.code1;
  const Observation* p2 = pair.code2;
  Candidate c;
  c.satellite = sat;
  c.code_if_m = pair.code_m();
  if (smoothed_codes) {
    const auto it = smoothed_codes->find(sat);
    if (it != smoothed_codes->end()) c.code_if_m = it->second;
  }
  // Transmission time: t_rx - P/c - dt_sat (two passes for dt_sat).
  GnssTime t_tx = epoch.time - *p1->value / kSpeedOfLight_mps;
  BroadcastLookup state;
  for (int pass = 0; pass < 2; ++pass) {
    state = ephemerides.state(sat, t_tx);
    if (!state) break;
    t_tx = epoch.time - *p1->value / kSpeedOfLight_mps - state.state->clock_bias_s;
  }
  if (!state) return std::nullopt;
  double clock_s = state.state->clock_bias_s;
  // A Galileo I/NAV clock refers to E1/E5b; an E1/E5a pair takes the difference of the two BGDs.
  if (sat.system == GnssSystem::Galileo && p2->code.band == '5') {
    const auto record = ephemerides.galileo(sat, t_tx);
    if (!record || !record.record->bgd_e5b_e1_s) return std::nullopt;
    clock_s += record.record->bgd_e5a_e1_s - *record.record->bgd_e5b_e1_s;
  }
  c.position_ecef_m = state.state->position_ecef_m;
  c.clock_m = clock_s * kSpeedOfLight_mps;
  return c;
}

/// The linearized code equations of one iteration, one row per satellite used.
struct CodeEquations {
  std::vector<Eigen::RowVectorXd> rows;  // position (3), then one column per receiver clock
  std::vector<double> rhs, weights;
  std::vector<std::size_t> index;        // candidate of each row
};

/// Code equations at x: Earth rotation during the flight time; above 6000 km from the
/// centre, the elevation mask, a Saastamoinen/Niell troposphere and sin^2(el) weights.
CodeEquations linearize(const std::vector<Candidate>& candidates, const std::vector<bool>& active,
                        const Eigen::Vector3d& x, const Eigen::VectorXd& clocks, bool near_earth, double doy,
                        const BroadcastSinglePointOptions& options) {
  const int n_clock = static_cast<int>(clocks.size());
  Geodetic geo;
  if (near_earth) geo = ecefToGeodetic(x);
  CodeEquations eq;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!active[i]) continue;
    const Candidate& c = candidates[i];
    // Earth rotation during the flight time.
    const double tau = (c.position_ecef_m - x).norm() / kSpeedOfLight_mps;
    const double angle = kEarthRotationRate_radps * tau;
    const Eigen::Vector3d sat(std::cos(angle) * c.position_ecef_m.x() + std::sin(angle) * c.position_ecef_m.y(),
                              -std::sin(angle) * c.position_ecef_m.x() + std::cos(angle) * c.position_ecef_m.y(),
                              c.position_ecef_m.z());
    const double range = (sat - x).norm();
    double trop = 0.0, weight = 1.0;
    if (near_earth) {
      const double el = azimuthElevation(x, sat).elevation_rad;
      if (el < options.elevation_mask_rad) continue;
      const SurfaceMeteo meteo = standardAtmosphere(geo.height_m);
      const MappingFunctions m = niellMapping(el, geo.latitude_rad, geo.height_m, doy);
      trop = saastamoinenZenithHydrostaticDelay_m(meteo.pressure_hpa, geo.latitude_rad, geo.height_m) * m.hydrostatic +
             saastamoinenZenithWetDelay_m(meteo) * m.wet;
      weight = std::sin(el) * std::sin(el);
    }
    Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(3 + n_clock);
    row.head<3>() = -(sat - x).transpose() / range;
    row(3 + c.system_column) = 1.0;
    eq.rows.push_back(row);
    eq.rhs.push_back(c.code_if_m - (range + clocks(c.system_column) - c.clock_m + trop));
    eq.weights.push_back(weight);
    eq.index.push_back(i);
  }
  return eq;
}

/// The clock columns with satellites: only those are estimated.
std::vector<int> liveClockColumns(const CodeEquations& eq, int n_clock) {
  std::vector<int> live;
  for (int k = 0; k < n_clock; ++k) {
    for (const auto& r : eq.rows)
      if (r(3 + k) != 0.0) {
        live.push_back(k);
        break;
      }
  }
  return live;
}

/// The receiver's position and clocks being estimated.
struct SinglePointState {
  Eigen::Vector3d x;
  Eigen::VectorXd clocks;  // [m], one per clock column
  int used = 0;            // satellites of the last iteration
};

enum class StepOutcome { Continue, Converged, Failed };

/// One weighted Gauss-Newton step; the satellites used and their residuals go to
/// `result`, and with convergence the receiver clocks.
StepOutcome gaussNewtonStep(const std::vector<Candidate>& candidates, const std::vector<bool>& active,
                            const std::map<GnssSystem, int>& columns, double doy,
                            const BroadcastSinglePointOptions& options, SinglePointState& s,
                            BroadcastSinglePointResult& result) {
  ++result.iterations;
  const bool near_earth = s.x.norm() > 6.0e6;
  const CodeEquations eq = linearize(candidates, active, s.x, s.clocks, near_earth, doy, options);
  const int used = s.used = static_cast<int>(eq.rows.size());
  const std::vector<int> live = liveClockColumns(eq, static_cast<int>(columns.size()));
  const int unknowns = 3 + static_cast<int>(live.size());
  if (used < unknowns) {
    result.reason = std::to_string(used) + " usable satellites, at least " + std::to_string(unknowns) + " needed";
    return StepOutcome::Failed;
  }
  Eigen::MatrixXd A(used, unknowns);
  Eigen::VectorXd b(used), w(used);
  for (int r = 0; r < used; ++r) {
    A.row(r).head<3>() = eq.rows[r].head<3>();
    for (std::size_t k = 0; k < live.size(); ++k) A(r, 3 + static_cast<int>(k)) = eq.rows[r](3 + live[k]);
    b(r) = eq.rhs[r];
    w(r) = eq.weights[r];
  }
  const Eigen::MatrixXd N = A.transpose() * w.asDiagonal() * A;
  const Eigen::VectorXd dx = N.ldlt().solve(A.transpose() * w.asDiagonal() * b);
  if (!dx.allFinite()) {
    result.reason = "singular geometry";
    return StepOutcome::Failed;
  }
  s.x += dx.head<3>();
  for (std::size_t k = 0; k < live.size(); ++k) s.clocks(live[k]) += dx(3 + static_cast<int>(k));
  const Eigen::VectorXd post = b - A * dx;
  result.used.clear();
  result.residuals_m.clear();
  for (int r = 0; r < used; ++r) {
    result.used.push_back(candidates[eq.index[r]].satellite);
    result.residuals_m.push_back(post(r));
  }
  if (!(dx.norm() < options.convergence_m && near_earth)) return StepOutcome::Continue;
  result.receiver_clock_m.clear();
  for (const auto& [system, k] : columns)
    if (std::find(live.begin(), live.end(), k) != live.end()) result.receiver_clock_m[system] = s.clocks(k);
  return StepOutcome::Converged;
}

/// Marks the satellite of the worst residual inactive when it is above the threshold
/// and redundancy remains; false when none is removed.
bool removeWorstOutlier(const std::vector<Candidate>& candidates, const BroadcastSinglePointResult& result, int used,
                        const BroadcastSinglePointOptions& options, std::vector<bool>& active) {
  std::size_t worst = 0;
  double worst_abs = 0.0;
  for (std::size_t r = 0; r < result.used.size(); ++r) {
    if (std::abs(result.residuals_m[r]) > worst_abs) {
      worst_abs = std::abs(result.residuals_m[r]);
      worst = r;
    }
  }
  const int unknowns = 3 + static_cast<int>(result.receiver_clock_m.size());
  if (!(worst_abs > options.outlier_threshold_m && used > unknowns + 1)) return false;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].satellite == result.used[worst]) active[i] = false;
  return true;
}

}  // namespace

BroadcastSinglePointResult broadcastSinglePoint(const ObsEpoch& epoch, const BroadcastEphemerisStore& ephemerides,
                                                const std::optional<Eigen::Vector3d>& start,
                                                const BroadcastSinglePointOptions& options,
                                                const std::map<SatelliteId, double>* smoothed_codes) {
  BroadcastSinglePointResult result;
  // 1. Candidates: an ionosphere-free code pair and a broadcast state at transmission;
  //    one receiver clock column per clock system, in the order first seen.
  std::vector<Candidate> candidates;
  std::map<GnssSystem, int> columns;
  for (const auto& entry : epoch.satellites) {
    auto c = candidateOf(epoch, entry.satellite, ephemerides, smoothed_codes);
    if (!c) continue;
    const GnssSystem system = singlePointRow(entry.satellite.system)->clock_system;
    c->system_column = columns.emplace(system, static_cast<int>(columns.size())).first->second;
    candidates.push_back(*c);
  }
  SinglePointState s{start.value_or(Eigen::Vector3d::Zero()),
                     Eigen::VectorXd::Zero(static_cast<int>(columns.size())), 0};
  std::vector<bool> active(candidates.size(), true);
  const double doy = epoch.time.dayOfYear();
  for (int round = 0; round < 10; ++round) {
    // 2. Gauss-Newton iterations to convergence.
    StepOutcome outcome = StepOutcome::Continue;
    for (int it = 0; it < options.max_iterations && outcome == StepOutcome::Continue; ++it)
      outcome = gaussNewtonStep(candidates, active, columns, doy, options, s, result);
    if (outcome == StepOutcome::Failed) return result;
    if (outcome != StepOutcome::Converged) {
      result.reason = "no convergence in " + std::to_string(options.max_iterations) + " iterations";
      return result;
    }
    // 3. The worst residual above the threshold removed while redundancy remains; then again.
    if (removeWorstOutlier(candidates, result, s.used, options, active)) continue;
    // 4. The solution.
    result.ok = true;
    result.position_ecef_m = s.x;
    return result;
  }
  result.reason = "too many outliers";
  return result;
}

}  // namespace ppp
