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
}  // namespace

std::string SsrCheckResult::lastLine() const {
  return format("orbit 3D RMS %.4f m, clock RMS %.3f ns, %zu satellite-epochs", orbit_rms_3d_m, clock_rms_ns,
                satellite_epochs);
}

SsrCheckResult checkSsrAgainstSp3(const SsrCheckRequest& req) {
  SsrCheckResult out;
  std::vector<NavData> navs;
  std::optional<GnssTime> ref;
  for (const auto& path : req.nav) {
    navs.push_back(readRinexNav(path));
    if (!ref && navs.back().last_toc) ref = navs.back().last_toc;
  }
  // A short SP3 (e.g. an ultra-rapid cut-out of 7 epochs) gets a Lagrange window
  // of all its epochs instead of the default 10.
  PreciseEphemeris sp3 = PreciseEphemeris::load({req.sp3}, req.clk);
  if (const auto span = sp3.orbitSpan(); span && sp3.orbitInterval_s() > 0.0) {
    const int nodes = static_cast<int>(std::lround((span->last - span->first) / sp3.orbitInterval_s())) + 1;
    if (nodes < PreciseEphemerisOptions{}.interpolation_points && nodes >= 2) {
      PreciseEphemerisOptions options;
      options.interpolation_points = nodes;
      sp3 = PreciseEphemeris::load({req.sp3}, req.clk, options);
      out.notes.push_back("SP3 of " + std::to_string(nodes) + " epochs: Lagrange interpolation over all of them");
    }
  }
  if (!ref && sp3.orbitSpan()) ref = sp3.orbitSpan()->first;
  const SsrStreamFile stream = readSsrStreamFile(req.ssr, ref);
  out.notes.push_back("stream " + fileBaseName(req.ssr) + ": " + std::to_string(stream.counters.frames) + " frames, " +
                      std::to_string(stream.counters.totalProblems()) + " problem(s)");
  for (std::size_t i = 0; i < stream.counters.problems.size() && i < 5; ++i)
    out.notes.push_back("  " + stream.counters.problems[i].describe());
  auto store = std::make_shared<SsrCorrectionStore>();
  for (const auto& m : stream.messages) store->add(m);

  out.reference = referenceUsed(req);
  BroadcastSsrOptions options;
  options.reference = out.reference;
  const BroadcastSsrEphemeris corrected(navs, store, options);
  for (std::size_t i = 0; i < corrected.consistency().problems.size() && i < 5; ++i)
    out.notes.push_back("  " + corrected.consistency().problems[i].describe());
  if (!corrected.satellitesWithoutBroadcast().empty())
    out.notes.push_back(std::to_string(corrected.satellitesWithoutBroadcast().size()) +
                        " satellite(s) with SSR corrections but no broadcast record in the navigation file(s)");
  if (corrected.consistency().totalProblems() > 0)
    out.notes.push_back(std::to_string(corrected.consistency().totalProblems()) +
                        " SSR orbit correction(s) without a broadcast record of their IOD");

  std::unique_ptr<AntexCalibrations> antex;
  if (req.atx) antex = std::make_unique<AntexCalibrations>(std::vector<AntexSource>{{fileBaseName(*req.atx), readAntexFile(*req.atx)}});
  const bool apc = out.reference != EphemerisReference::CentreOfMass;
  const bool l1 = out.reference == EphemerisReference::AntennaPhaseCentreL1;
  if (!apc) out.reference_handling = "stream at the centre of mass: compared with the SP3 (centre of mass) directly";
  else if (antex)
    out.reference_handling = std::string("stream at the antenna phase centre: SP3 moved to the APC by the ") +
                             (l1 ? "L1 (E1)" : "ionosphere-free L1/L2 (E1/E5a)") +
                             " satellite PCO of " + fileBaseName(*req.atx) + " (nominal yaw attitude)";
  else out.reference_handling = "stream at the antenna phase centre, no ANTEX given: compared with the SP3 centre of mass as is (differs by the satellite PCO)";

  // Epochs: every SSR orbit epoch.
  std::set<GnssTime> epochs;
  for (const auto& [sat, series] : store->orbits())
    for (const auto& [t0, e] : series) epochs.insert(t0);

  struct Acc {
    std::size_t n = 0, nc = 0;
    double s3 = 0, sr = 0, sa = 0, sc = 0, sclk = 0;
    bool pco = false;
  };
  std::map<SatelliteId, Acc> acc;
  std::set<std::string> missing_pco;
  double total3 = 0.0, total_clk = 0.0;
  for (const GnssTime& t : epochs) {
    std::vector<std::pair<SatelliteId, double>> clock_diffs_ns;
    for (const auto& [sat, series] : store->orbits()) {
      if (std::find(req.systems.begin(), req.systems.end(), sat.system) == req.systems.end()) continue;
      const auto cs = corrected.correctedState(sat, t);
      if (!cs.ok()) continue;
      const auto po = sp3.satelliteOrbit(sat, t);
      if (!po.ok()) continue;
      Eigen::Vector3d ref_pos = po.value->position_ecef_m;
      bool pco_applied = false;
      if (apc && antex) {
        const auto cal = antex->satellite(sat, t);
        const auto [b1, b2] = ssrIonosphereFreeBands(sat.system);
        const auto fr1 = carrierFrequency_hz(sat.system, b1);
        const auto fr2 = carrierFrequency_hz(sat.system, b2);
        const auto offset = fr1 && fr2 ? satelliteReferenceOffset_m(out.reference, cal.calibration, sat.system, b1, b2,
                                                                   ionosphereFreeCoefficients(*fr1, *fr2))
                                       : std::nullopt;
        if (offset) {
          const Eigen::Vector3d& pco = *offset;
          const SatelliteBodyAxes axes =
              nominalSatelliteAxes(ref_pos, po.value->velocity_ecef_mps, sunPositionEcef_m(t));
          ref_pos += pco.x() * axes.x_ecef + pco.y() * axes.y_ecef + pco.z() * axes.z_ecef;
          pco_applied = true;
        } else {
          missing_pco.insert(sat.toString());
        }
      }
      const Eigen::Vector3d d = cs.value->position_ecef_m - ref_pos;
      const Eigen::Vector3d& r = ref_pos;
      const Eigen::Vector3d& v = po.value->velocity_ecef_mps;
      const Eigen::Vector3d e_a = v.normalized(), e_c = r.cross(v).normalized(), e_r = e_a.cross(e_c);
      Acc& a = acc[sat];
      a.n += 1;
      a.s3 += d.squaredNorm();
      a.sr += std::pow(d.dot(e_r), 2);
      a.sa += std::pow(d.dot(e_a), 2);
      a.sc += std::pow(d.dot(e_c), 2);
      a.pco = a.pco || pco_applied;
      total3 += d.squaredNorm();
      out.satellite_epochs += 1;
      const auto pc = sp3.satelliteClock(sat, t);
      if (pc.ok()) clock_diffs_ns.emplace_back(sat, (cs.value->clock_s - pc.value->clock_bias_s) * 1e9);
    }
    if (clock_diffs_ns.size() >= 2) {
      double mean = 0.0;
      for (const auto& [s, d] : clock_diffs_ns) mean += d;
      mean /= static_cast<double>(clock_diffs_ns.size());
      for (const auto& [s, d] : clock_diffs_ns) {
        acc[s].nc += 1;
        acc[s].sclk += (d - mean) * (d - mean);
        total_clk += (d - mean) * (d - mean);
        out.clock_satellite_epochs += 1;
      }
    }
  }
  for (const auto& [sat, a] : acc) {
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
  if (out.satellite_epochs > 0) out.orbit_rms_3d_m = std::sqrt(total3 / static_cast<double>(out.satellite_epochs));
  if (out.clock_satellite_epochs > 0)
    out.clock_rms_ns = std::sqrt(total_clk / static_cast<double>(out.clock_satellite_epochs));
  if (!missing_pco.empty()) {
    std::string list;
    for (const auto& s : missing_pco) list += " " + s;
    out.notes.push_back("no satellite PCO in the ANTEX file for:" + list + " (compared at the centre of mass)");
  }
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
