#include "ppp_bayes_tree/evaluation/ssr_check.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <set>
#include <sstream>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/broadcast_ssr_ephemeris.h"
#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

namespace {

/// The reference point used: the request's (or the stream name's, else APC L1),
/// with an APC flavour given by `apc` taking precedence.
EphemerisReference referenceUsed(const SsrCheckRequest& req) {
  EphemerisReference r = req.reference ? *req.reference
                                       : ssrReferenceFromStreamName(fileBaseName(req.ssr))
                                             .value_or(EphemerisReference::AntennaPhaseCentreL1);
  if (r != EphemerisReference::CentreOfMass && req.apc)
    r = *req.apc == SsrApcFrequency::FirstFrequency ? EphemerisReference::AntennaPhaseCentreL1
                                                    : EphemerisReference::AntennaPhaseCentre;
  return r;
}

// The broadcast navigation files and the reference time for the stream's week (the first last toc).
struct NavigationInput {
  std::vector<NavData> navs;
  std::optional<GnssTime> reference_time;
};

// Sums of squares of one satellite's differences over the epochs [m^2, ns^2].
struct SatelliteSums {
  std::size_t n = 0, nc = 0;
  double s3 = 0, sr = 0, sa = 0, sc = 0, sclk = 0;
  bool pco = false;
};

// Sums over all satellites and epochs [m^2, ns^2], and the satellites lacking a PCO.
struct CheckSums {
  std::map<SatelliteId, SatelliteSums> satellites;
  std::set<std::string> missing_pco;
  double total3_m2 = 0.0, total_clk_ns2 = 0.0;
};

// What every epoch's comparison reads: the request, both ephemerides, the ANTEX and the reference.
struct ComparisonInputs {
  const SsrCheckRequest& req;
  const SsrCorrectionStore& store;
  const BroadcastSsrEphemeris& corrected;
  const PreciseEphemeris& sp3;
  const AntexCalibrations* antex;
  EphemerisReference reference;
};

// Step 1: the navigation files read, the reference time from the first with a last toc.
NavigationInput readNavigation(const SsrCheckRequest& req) {
  NavigationInput in;
  for (const auto& path : req.nav) {
    in.navs.push_back(readRinexNav(path));
    if (!in.reference_time && in.navs.back().last_toc) in.reference_time = in.navs.back().last_toc;
  }
  return in;
}

// Step 2: the SP3 (and clocks); a short SP3 (e.g. an ultra-rapid cut-out of 7 epochs) gets a
// Lagrange window of all its epochs instead of the default 10.
PreciseEphemeris loadPreciseEphemeris(const SsrCheckRequest& req, std::vector<std::string>& notes) {
  PreciseEphemeris sp3 = PreciseEphemeris::load({req.sp3}, req.clk);
  if (const auto span = sp3.orbitSpan(); span && sp3.orbitInterval_s() > 0.0) {
    const int nodes = static_cast<int>(std::lround((span->last - span->first) / sp3.orbitInterval_s())) + 1;
    if (nodes < PreciseEphemerisOptions{}.interpolation_points && nodes >= 2) {
      PreciseEphemerisOptions options;
      options.interpolation_points = nodes;
      sp3 = PreciseEphemeris::load({req.sp3}, req.clk, options);
      notes.push_back("SP3 of " + std::to_string(nodes) + " epochs: Lagrange interpolation over all of them");
    }
  }
  return sp3;
}

// Step 3: the stream's frame and problem counts (the first 5 problems) as notes.
void noteStreamDecoding(const SsrCheckRequest& req, const SsrStreamFile& stream, std::vector<std::string>& notes) {
  notes.push_back("stream " + fileBaseName(req.ssr) + ": " + std::to_string(stream.counters.frames) + " frames, " +
                  std::to_string(stream.counters.totalProblems()) + " problem(s)");
  for (std::size_t i = 0; i < stream.counters.problems.size() && i < 5; ++i)
    notes.push_back("  " + stream.counters.problems[i].describe());
}

// Step 4: the corrections without a broadcast record (first 5, then the counts) as notes.
void noteBroadcastConsistency(const BroadcastSsrEphemeris& corrected, std::vector<std::string>& notes) {
  for (std::size_t i = 0; i < corrected.consistency().problems.size() && i < 5; ++i)
    notes.push_back("  " + corrected.consistency().problems[i].describe());
  if (!corrected.satellitesWithoutBroadcast().empty())
    notes.push_back(std::to_string(corrected.satellitesWithoutBroadcast().size()) +
                    " satellite(s) with SSR corrections but no broadcast record in the navigation file(s)");
  if (corrected.consistency().totalProblems() > 0)
    notes.push_back(std::to_string(corrected.consistency().totalProblems()) +
                    " SSR orbit correction(s) without a broadcast record of their IOD");
}

// Step 5: one line for people on how the SP3 is brought to the stream's reference point.
std::string referenceHandling(const SsrCheckRequest& req, EphemerisReference reference, bool have_antex) {
  const bool apc = reference != EphemerisReference::CentreOfMass;
  const bool l1 = reference == EphemerisReference::AntennaPhaseCentreL1;
  if (!apc) return "stream at the centre of mass: compared with the SP3 (centre of mass) directly";
  if (have_antex)
    return std::string("stream at the antenna phase centre: SP3 moved to the APC by the ") +
           (l1 ? "L1 (E1)" : "ionosphere-free L1/L2 (E1/E5a)") + " satellite PCO of " + fileBaseName(*req.atx) +
           " (nominal yaw attitude)";
  return "stream at the antenna phase centre, no ANTEX given: compared with the SP3 centre of mass as is (differs by the satellite PCO)";
}

// The SP3 position [m] moved to the stream's antenna phase centre by the satellite PCO when the
// reference is an APC and the ANTEX has it; `pco_applied` says whether it was.
Eigen::Vector3d referencePosition_m(const ComparisonInputs& in, const SatelliteId& sat, const GnssTime& t,
                                    const Eigen::Vector3d& sp3_position_m, const Eigen::Vector3d& sp3_velocity_mps,
                                    bool& pco_applied, CheckSums& sums) {
  Eigen::Vector3d ref_pos = sp3_position_m;
  pco_applied = false;
  if (in.reference == EphemerisReference::CentreOfMass || !in.antex) return ref_pos;
  const auto cal = in.antex->satellite(sat, t);
  const auto [b1, b2] = ssrIonosphereFreeBands(sat.system);
  const auto fr1 = carrierFrequency_hz(sat.system, b1);
  const auto fr2 = carrierFrequency_hz(sat.system, b2);
  const auto offset = fr1 && fr2 ? satelliteReferenceOffset_m(in.reference, cal.calibration, sat.system, b1, b2,
                                                             ionosphereFreeCoefficients(*fr1, *fr2))
                                 : std::nullopt;
  if (offset) {
    const Eigen::Vector3d& pco = *offset;
    const SatelliteBodyAxes axes = nominalSatelliteAxes(ref_pos, sp3_velocity_mps, sunPositionEcef_m(t));
    ref_pos += pco.x() * axes.x_ecef + pco.y() * axes.y_ecef + pco.z() * axes.z_ecef;
    pco_applied = true;
  } else {
    sums.missing_pco.insert(sat.toString());
  }
  return ref_pos;
}

// The orbit difference [m] added to the satellite's sums in 3D and radial/along/cross.
void addOrbitDifference(const SatelliteId& sat, const Eigen::Vector3d& d, const Eigen::Vector3d& r,
                        const Eigen::Vector3d& v, bool pco_applied, CheckSums& sums, SsrCheckResult& out) {
  const Eigen::Vector3d e_a = v.normalized(), e_c = r.cross(v).normalized(), e_r = e_a.cross(e_c);
  SatelliteSums& a = sums.satellites[sat];
  a.n += 1;
  a.s3 += d.squaredNorm();
  a.sr += std::pow(d.dot(e_r), 2);
  a.sa += std::pow(d.dot(e_a), 2);
  a.sc += std::pow(d.dot(e_c), 2);
  a.pco = a.pco || pco_applied;
  sums.total3_m2 += d.squaredNorm();
  out.satellite_epochs += 1;
}

// An epoch's clock differences [ns] added to the sums, less their mean (each product has its own
// clock datum); only with two satellites or more.
void addClockDifferences_ns(const std::vector<std::pair<SatelliteId, double>>& clock_diffs_ns, CheckSums& sums,
                            SsrCheckResult& out) {
  if (clock_diffs_ns.size() < 2) return;
  double mean = 0.0;
  for (const auto& [s, d] : clock_diffs_ns) mean += d;
  mean /= static_cast<double>(clock_diffs_ns.size());
  for (const auto& [s, d] : clock_diffs_ns) {
    sums.satellites[s].nc += 1;
    sums.satellites[s].sclk += (d - mean) * (d - mean);
    sums.total_clk_ns2 += (d - mean) * (d - mean);
    out.clock_satellite_epochs += 1;
  }
}

// Step 6 (per SSR orbit epoch): every satellite of the requested systems with a corrected and an
// SP3 orbit compared, then the epoch's clocks.
void compareEpoch(const ComparisonInputs& in, const GnssTime& t, CheckSums& sums, SsrCheckResult& out) {
  std::vector<std::pair<SatelliteId, double>> clock_diffs_ns;
  for (const auto& [sat, series] : in.store.orbits()) {
    if (std::find(in.req.systems.begin(), in.req.systems.end(), sat.system) == in.req.systems.end()) continue;
    const auto cs = in.corrected.correctedState(sat, t);
    if (!cs.ok()) continue;
    const auto po = in.sp3.satelliteOrbit(sat, t);
    if (!po.ok()) continue;
    bool pco_applied = false;
    const Eigen::Vector3d ref_pos =
        referencePosition_m(in, sat, t, po.value->position_ecef_m, po.value->velocity_ecef_mps, pco_applied, sums);
    const Eigen::Vector3d d = cs.value->position_ecef_m - ref_pos;
    addOrbitDifference(sat, d, ref_pos, po.value->velocity_ecef_mps, pco_applied, sums, out);
    const auto pc = in.sp3.satelliteClock(sat, t);
    if (pc.ok()) clock_diffs_ns.emplace_back(sat, (cs.value->clock_s - pc.value->clock_bias_s) * 1e9);
  }
  addClockDifferences_ns(clock_diffs_ns, sums, out);
}

// Step 7: per-satellite and overall RMS [m, ns] from the sums, and the satellites lacking a PCO.
void summarise(const CheckSums& sums, SsrCheckResult& out) {
  for (const auto& [sat, a] : sums.satellites) {
    SsrCheckSatellite s;
    s.satellite = sat;
    s.epochs = a.n;
    const double n = static_cast<double>(std::max<std::size_t>(a.n, 1));
    s.orbit_rms_3d_m = std::sqrt(a.s3 / n);
    s.radial_rms_m = std::sqrt(a.sr / n);
    s.along_rms_m = std::sqrt(a.sa / n);
    s.cross_rms_m = std::sqrt(a.sc / n);
    s.clock_epochs = a.nc;
    s.clock_rms_ns = a.nc > 0 ? std::sqrt(a.sclk / static_cast<double>(a.nc)) : 0.0;
    s.pco_applied = a.pco;
    out.satellites.push_back(s);
  }
  if (out.satellite_epochs > 0)
    out.orbit_rms_3d_m = std::sqrt(sums.total3_m2 / static_cast<double>(out.satellite_epochs));
  if (out.clock_satellite_epochs > 0)
    out.clock_rms_ns = std::sqrt(sums.total_clk_ns2 / static_cast<double>(out.clock_satellite_epochs));
  if (!sums.missing_pco.empty()) {
    std::string list;
    for (const auto& s : sums.missing_pco) list += " " + s;
    out.notes.push_back("no satellite PCO in the ANTEX file for:" + list + " (compared at the centre of mass)");
  }
}

}  // namespace

std::string SsrCheckResult::lastLine() const {
  return format("orbit 3D RMS %.4f m, clock RMS %.3f ns, %zu satellite-epochs", orbit_rms_3d_m, clock_rms_ns,
                satellite_epochs);
}

SsrCheckResult checkSsrAgainstSp3(const SsrCheckRequest& req) {
  SsrCheckResult out;
  // 1-2. Broadcast navigation, the SP3 and the stream's reference time.
  const NavigationInput nav = readNavigation(req);
  const PreciseEphemeris sp3 = loadPreciseEphemeris(req, out.notes);
  std::optional<GnssTime> ref = nav.reference_time;
  if (!ref && sp3.orbitSpan()) ref = sp3.orbitSpan()->first;
  // 3. The stream decoded into a correction store.
  const SsrStreamFile stream = readSsrStreamFile(req.ssr, ref);
  noteStreamDecoding(req, stream, out.notes);
  auto store = std::make_shared<SsrCorrectionStore>();
  for (const auto& m : stream.messages) store->add(m);
  // 4. Broadcast + SSR at the stream's reference point.
  out.reference = referenceUsed(req);
  BroadcastSsrOptions options;
  options.reference = out.reference;
  const BroadcastSsrEphemeris corrected(nav.navs, store, options);
  noteBroadcastConsistency(corrected, out.notes);
  // 5. The satellite antenna offsets for an APC stream.
  std::unique_ptr<AntexCalibrations> antex;
  if (req.atx) antex = std::make_unique<AntexCalibrations>(std::vector<AntexSource>{{fileBaseName(*req.atx), readAntexFile(*req.atx)}});
  out.reference_handling = referenceHandling(req, out.reference, antex != nullptr);
  // 6. Every SSR orbit epoch compared.
  std::set<GnssTime> epochs;
  for (const auto& [sat, series] : store->orbits())
    for (const auto& [t0, e] : series) epochs.insert(t0);
  const ComparisonInputs inputs{req, *store, corrected, sp3, antex.get(), out.reference};
  CheckSums sums;
  for (const GnssTime& t : epochs) compareEpoch(inputs, t, sums, out);
  // 7. RMS per satellite and overall, then the stream summary.
  summarise(sums, out);
  out.notes.push_back("SSR summary:\n" + stream.summary.format());
  return out;
}

std::string formatSsrCheck(const SsrCheckResult& r) {
  std::ostringstream o;
  for (const auto& n : r.notes) o << n << "\n";
  o << "reference point: " << r.reference_handling << "\n";
  o << "sat  epochs  3D_rms_m  radial_m  along_m  cross_m  clock_epochs  clock_rms_ns  pco\n";
  for (const auto& s : r.satellites) {
    o << format("%s %7zu %9.3f %9.3f %8.3f %8.3f %13zu %13.3f  %s\n", s.satellite.toString().c_str(), s.epochs,
                s.orbit_rms_3d_m, s.radial_rms_m, s.along_rms_m, s.cross_rms_m, s.clock_epochs, s.clock_rms_ns,
                s.pco_applied ? "yes" : "no");
  }
  o << r.lastLine() << "\n";
  return o.str();
}

}  // namespace ppp
