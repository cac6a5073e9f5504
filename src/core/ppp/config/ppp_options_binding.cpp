#include "ppp_bayes_tree/ppp/config/ppp_options_binding.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace ppp {
namespace {

/// Tracking-mode attribute letters (RINEX 3.05 sec. 5.1: one upper-case letter, or X/Z...).
std::vector<char> readAttributes(YamlSection& s, const std::string& key, const std::vector<char>& fallback) {
  std::vector<std::string> text;
  for (char c : fallback) text.emplace_back(1, c);
  std::vector<char> out;
  for (const auto& a : s.textList(key, text)) {
    if (a.size() != 1 || !std::isupper(static_cast<unsigned char>(a[0])))
      s.fail(key, "expected RINEX 3 tracking-mode letters (e.g. [W, C]), got '" + a + "'");
    if (std::find(out.begin(), out.end(), a[0]) != out.end()) s.fail(key, "letter '" + a + "' given twice");
    out.push_back(a[0]);
  }
  return out;
}

void readPriority(YamlSection s, SystemSignalPriority& p) {
  p.code1_attributes = readAttributes(s, "code1", p.code1_attributes);
  p.code2_attributes = readAttributes(s, "code2", p.code2_attributes);
  p.phase1_attributes = readAttributes(s, "phase1", p.phase1_attributes);
  p.phase2_attributes = readAttributes(s, "phase2", p.phase2_attributes);
  p.code_sigma_factor = s.number("code_sigma_factor", p.code_sigma_factor, Bound::Positive);
  s.finish();
}

void readSignals(YamlSection s, SignalSelectionOptions& o) {
  // `auto` (or no key): the systems the products and antennas cover; a list: exactly those.
  const bool automatic = s.hasScalar("systems") && s.text("systems", "") == "auto";
  if (automatic) o.systems_from_products = true;
  else if (s.has("systems")) o.systems_from_products = false;
  std::vector<std::string> names;
  for (auto sys : o.systems) names.emplace_back(systemName(sys));
  std::vector<GnssSystem> systems;
  for (const auto& n : automatic ? names : s.textList("systems", names)) {
    // A system of the signal table, by name ("BeiDou") or RINEX letter ("C").
    const auto row = std::find_if(signalTable().begin(), signalTable().end(), [&n](const SignalTableRow& r) {
      return n == systemName(r.system) || n == std::string(1, systemLetter(r.system));
    });
    if (row == signalTable().end())
      s.fail("systems", "expected " + signalTableSystemNames() + " (the systems with an IF frequency pair), got '" +
                            n + "'");
    const GnssSystem sys = row->system;
    if (std::find(systems.begin(), systems.end(), sys) != systems.end()) s.fail("systems", "'" + n + "' given twice");
    systems.push_back(sys);
  }
  o.systems = systems;
  o.require_code_osb = s.boolean("require_code_osb", o.require_code_osb);
  const std::string shift = s.choice("phase_shift",
                                     o.phase_shift == PhaseShiftHandling::AsWritten ? "as_written" : "restore_original",
                                     {"as_written", "restore_original"});
  o.phase_shift = shift == "as_written" ? PhaseShiftHandling::AsWritten : PhaseShiftHandling::RestoreOriginal;
  for (const auto& row : signalTable()) readPriority(s.section(row.config_key), o.priorities[row.system]);
  s.finish();
}

}  // namespace

std::string toString(DryTroposphereModel model) {
  return model == DryTroposphereModel::Saastamoinen ? "saastamoinen" : "modified_hopfield";
}

std::string toString(TroposphereMapping mapping) {
  switch (mapping) {
    case TroposphereMapping::Niell: return "niell";
    case TroposphereMapping::Gmf: return "gmf";
    default: return "modified_hopfield";
  }
}

void bindMeasurementModelOptions(const YAML::Node& node, const std::string& file, MeasurementModelOptions& m,
                                 SignalSelectionOptions& signals) {
  YamlSection s(node, file, "measurement_model");
  const double cutoff_deg = s.number("elevation_cutoff_deg", m.elevation_cutoff_rad * kRadToDeg, Bound::NonNegative);
  if (cutoff_deg >= 90.0) s.fail("elevation_cutoff_deg", "must be below 90 deg");
  m.elevation_cutoff_rad = cutoff_deg * kDegToRad;
  m.phase_sigma_zenith_m = s.number("phase_sigma_zenith_m", m.phase_sigma_zenith_m, Bound::Positive);
  m.code_phase_ratio = s.number("code_phase_ratio", m.code_phase_ratio, Bound::Positive);
  m.scale_sigma_for_ionosphere_free = s.boolean("scale_sigma_for_ionosphere_free", m.scale_sigma_for_ionosphere_free);
  m.ephemeris_sigmas = s.boolean("ephemeris_sigmas", m.ephemeris_sigmas);
  {
    YamlSection t = s.section("troposphere");
    const std::string dry = t.choice("dry_model", toString(m.dry_troposphere), {"modified_hopfield", "saastamoinen"});
    m.dry_troposphere = dry == "saastamoinen" ? DryTroposphereModel::Saastamoinen : DryTroposphereModel::ModifiedHopfield;
    const std::string map = t.choice("mapping", toString(m.mapping), {"modified_hopfield", "niell", "gmf"});
    m.mapping = map == "niell" ? TroposphereMapping::Niell
                : map == "gmf" ? TroposphereMapping::Gmf
                               : TroposphereMapping::ModifiedHopfield;
    m.estimate_troposphere_gradients = t.boolean("estimate_gradients", m.estimate_troposphere_gradients);
    m.zwd_at_ellipsoid = t.boolean("zwd_at_ellipsoid", m.zwd_at_ellipsoid);
    t.finish();
  }
  {
    YamlSection c = s.section("corrections");
    m.solid_earth_tide = c.boolean("solid_earth_tide", m.solid_earth_tide);
    m.ocean_loading = c.boolean("ocean_loading", m.ocean_loading);
    m.phase_windup = c.boolean("phase_windup", m.phase_windup);
    m.satellite_antenna = c.boolean("satellite_antenna", m.satellite_antenna);
    // required | warn | off; the former boolean spelling: true = required, false = off.
    const std::string policy = c.choice("receiver_antenna", std::string(receiverAntennaPolicyName(m.receiver_antenna)),
                                        {"required", "warn", "off", "true", "false"});
    m.receiver_antenna = policy == "required" || policy == "true" ? ReceiverAntennaPolicy::Required
                         : policy == "off" || policy == "false"   ? ReceiverAntennaPolicy::Off
                                                                  : ReceiverAntennaPolicy::Warn;
    const std::string substitution =
        c.choice("receiver_frequency_substitution",
                 std::string(receiverFrequencySubstitutionName(m.receiver_frequency_substitution)), {"gps", "none"});
    m.receiver_frequency_substitution =
        substitution == "none" ? ReceiverFrequencySubstitution::None : ReceiverFrequencySubstitution::Gps;
    m.shapiro = c.boolean("shapiro", m.shapiro);
    m.exclude_eclipse = c.boolean("exclude_eclipse", m.exclude_eclipse);
    const std::string yaw = c.choice("yaw_manoeuvre", std::string(yawManoeuvreHandlingName(m.yaw_manoeuvre)),
                                     {"model", "exclude", "nominal"});
    m.yaw_manoeuvre = yaw == "exclude"   ? YawManoeuvreHandling::Exclude
                      : yaw == "nominal" ? YawManoeuvreHandling::Nominal
                                         : YawManoeuvreHandling::Model;
    c.finish();
  }
  readSignals(s.section("signals"), signals);
  s.finish();
}

void bindCycleSlipOptions(const YAML::Node& node, const std::string& file, CycleSlipOptions& o) {
  YamlSection s(node, file, "cycle_slip");
  {
    YamlSection mw = s.section("melbourne_wuebbena");
    o.mw_sigma_factor = mw.number("sigma_factor", o.mw_sigma_factor, Bound::Positive);
    o.mw_min_threshold_cycles = mw.number("min_threshold_cycles", o.mw_min_threshold_cycles, Bound::Positive);
    o.mw_initial_sigma_cycles = mw.number("initial_sigma_cycles", o.mw_initial_sigma_cycles, Bound::Positive);
    o.mw_min_samples = mw.integer("min_samples", o.mw_min_samples, 1);
    o.mw_window = mw.integer("window", o.mw_window, 1);
    mw.finish();
  }
  {
    YamlSection gf = s.section("geometry_free");
    o.gf_threshold_base_m = gf.number("threshold_base_m", o.gf_threshold_base_m, Bound::Positive);
    o.gf_threshold_rate_mps = gf.number("threshold_rate_m_per_s", o.gf_threshold_rate_mps, Bound::NonNegative);
    o.gf_threshold_max_m = gf.number("threshold_max_m", o.gf_threshold_max_m, Bound::Positive);
    if (o.gf_threshold_max_m < o.gf_threshold_base_m)
      gf.fail("threshold_max_m", "must be >= threshold_base_m");
    o.gf_fit_points = gf.integer("fit_points", o.gf_fit_points, 2);
    o.gf_drift_allowance_mps = gf.number("drift_allowance_m_per_s", o.gf_drift_allowance_mps, Bound::NonNegative);
    o.gf_sigma_factor = gf.number("sigma_factor", o.gf_sigma_factor, Bound::Positive);
    o.gf_min_samples = gf.integer("min_samples", o.gf_min_samples, 1);
    gf.finish();
  }
  {
    // max_gap_s: a number of seconds, or "auto" (max_gap_intervals x the data interval).
    const std::string gap = s.text("max_gap_s", o.max_gap_s ? std::to_string(*o.max_gap_s) : "auto");
    if (gap == "auto") {
      o.max_gap_s.reset();
    } else {
      o.max_gap_s = s.number("max_gap_s", 0.0, Bound::Positive);
    }
  }
  o.max_gap_intervals = s.number("max_gap_intervals", o.max_gap_intervals, Bound::Positive);
  o.default_interval_s = s.number("default_interval_s", o.default_interval_s, Bound::Positive);
  o.use_loss_of_lock = s.boolean("use_loss_of_lock", o.use_loss_of_lock);
  {
    YamlSection r = s.section("slip_repair");
    SlipRepairOptions& p = o.slip_repair;
    p.enabled = r.boolean("enabled", p.enabled);
    p.max_wide_lane_offset_cycles =
        r.number("max_wide_lane_offset_cycles", p.max_wide_lane_offset_cycles, Bound::Positive);
    p.max_wide_lane_sigma_cycles = r.number("max_wide_lane_sigma_cycles", p.max_wide_lane_sigma_cycles, Bound::Positive);
    p.max_l1_fraction_cycles = r.number("max_l1_fraction_cycles", p.max_l1_fraction_cycles, Bound::Positive);
    p.max_l1_sigma_cycles = r.number("max_l1_sigma_cycles", p.max_l1_sigma_cycles, Bound::Positive);
    p.gf_fit_window_s = r.number("gf_fit_window_s", p.gf_fit_window_s, Bound::Positive);
    p.gf_fit_min_points = r.integer("gf_fit_min_points", p.gf_fit_min_points, 3);
    p.gf_fit_order = r.integer("gf_fit_order", p.gf_fit_order, 1);
    if (p.gf_fit_order > 2) r.fail("gf_fit_order", "must be 1 (linear) or 2 (quadratic)");
    p.phase_sigma_m = r.number("phase_sigma_m", p.phase_sigma_m, Bound::Positive);
    p.ionosphere_sigma_mps = r.number("ionosphere_sigma_m_per_s", p.ionosphere_sigma_mps, Bound::NonNegative);
    p.max_candidate_wide_lane_sigma_cycles = r.number("max_candidate_wide_lane_sigma_cycles",
                                                      p.max_candidate_wide_lane_sigma_cycles, Bound::NonNegative);
    p.candidate_sigma_factor = r.number("candidate_sigma_factor", p.candidate_sigma_factor, Bound::Positive);
    p.min_candidate_half_width_cycles =
        r.number("min_candidate_half_width_cycles", p.min_candidate_half_width_cycles, Bound::Positive);
    p.max_candidates = r.integer("max_candidates", p.max_candidates, 1);
    p.max_joint_misfit = r.number("max_joint_misfit", p.max_joint_misfit, Bound::NonNegative);
    r.finish();
  }
  s.finish();
}

}  // namespace ppp
