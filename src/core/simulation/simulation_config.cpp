#include "ppp_bayes_tree/simulation/simulation_config.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "ppp_bayes_tree/ppp/config/yaml_document.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

ErrorModelConfig ErrorModelConfig::none() {
  ErrorModelConfig e;
  e.thermal.enabled = false;
  e.multipath.enabled = false;
  e.troposphere.enabled = false;
  e.ionosphere.enabled = false;
  e.receiver_clock.enabled = false;
  e.ambiguity.enabled = false;
  e.phase_breaks.enabled = false;
  e.products.enabled = false;
  return e;
}

bool SimulationConfig::simulates(GnssSystem system) const {
  return std::find(systems.begin(), systems.end(), system) != systems.end();
}

const SimulationConfig::Outage* SimulationConfig::outageAt(double since_start_s) const {
  for (const Outage& o : outages)
    if (since_start_s >= o.start_s - 1e-9 && since_start_s < o.start_s + o.duration_s - 1e-9) return &o;
  return nullptr;
}

double defaultProfileDuration_s(FlightProfile profile) {
  switch (profile) {
    case FlightProfile::Loiter: return 40.0 * 60.0;
    case FlightProfile::Survey: return 45.0 * 60.0;
    case FlightProfile::Figure8: return 30.0 * 60.0;
    case FlightProfile::Climb: return 60.0 * 60.0;
  }
  return 1800.0;
}

double SimulationConfig::durationOrDefault_s() const {
  return duration_s ? *duration_s : defaultProfileDuration_s(profile);
}

namespace {

GnssTime parseStart(YamlSection& s, const std::string& key, const GnssTime& fallback) {
  const std::string text = s.text(key, "");
  if (text.empty()) return fallback;
  CalendarTime c;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%d %d:%d:%lf%c", &c.year, &c.month, &c.day, &c.hour, &c.minute, &c.second,
                  &tail) != 6 ||
      c.hour < 0 || c.hour > 23 || c.minute < 0 || c.minute > 59 || c.second < 0 || c.second >= 60.0 ||
      !isValidDate(c.year, c.month, c.day) || c.year < 1981 || c.year > 2100)
    s.fail(key, "expected \"YYYY-MM-DD hh:mm:ss\" (GPST), got \"" + text + "\"");
  return GnssTime::fromCalendar(c, TimeSystem::GPS);
}

void readRange(YamlSection& s, const char* lo_key, const char* hi_key, double& lo, double& hi, Bound bound) {
  lo = s.number(lo_key, lo, bound);
  hi = s.number(hi_key, hi, bound);
  if (lo > hi) s.fail(hi_key, std::string("must be >= ") + lo_key);
}

void readThermal(YamlSection t, ErrorModelConfig& e) {
  e.thermal.enabled = t.boolean("enabled", e.thermal.enabled);
  e.thermal.code_sigma_m = t.number("code_sigma_m", e.thermal.code_sigma_m, Bound::NonNegative);
  const std::string mode = t.choice("phase", e.thermal.phase_mode == PhaseNoiseMode::FixedSigma ? "fixed" : "wavelength_fraction",
                                    {"fixed", "wavelength_fraction"});
  e.thermal.phase_mode = mode == "fixed" ? PhaseNoiseMode::FixedSigma : PhaseNoiseMode::WavelengthFraction;
  e.thermal.phase_sigma_m = t.number("phase_sigma_m", e.thermal.phase_sigma_m, Bound::NonNegative);
  e.thermal.phase_sigma_cycles = t.number("phase_sigma_cycles", e.thermal.phase_sigma_cycles, Bound::NonNegative);
  t.finish();
}

void readMultipath(YamlSection m, ErrorModelConfig& e) {
  e.multipath.enabled = m.boolean("enabled", e.multipath.enabled);
  e.multipath.sigma_m = m.number("sigma_m", e.multipath.sigma_m, Bound::NonNegative);
  e.multipath.time_constant_s = m.number("time_constant_s", e.multipath.time_constant_s, Bound::Positive);
  m.finish();
}

void readTroposphere(YamlSection t, ErrorModelConfig& e) {
  e.troposphere.enabled = t.boolean("enabled", e.troposphere.enabled);
  readRange(t, "dry_scale_min", "dry_scale_max", e.troposphere.dry_scale_min, e.troposphere.dry_scale_max,
            Bound::NonNegative);
  readRange(t, "wet_scale_min", "wet_scale_max", e.troposphere.wet_scale_min, e.troposphere.wet_scale_max,
            Bound::NonNegative);
  t.finish();
}

void readIonosphere(YamlSection i, ErrorModelConfig& e) {
  e.ionosphere.enabled = i.boolean("enabled", e.ionosphere.enabled);
  readRange(i, "vtec_min_tecu", "vtec_max_tecu", e.ionosphere.vtec_min_tecu, e.ionosphere.vtec_max_tecu,
            Bound::NonNegative);
  e.ionosphere.vtec_rate_max_tecu_per_h =
      i.number("vtec_rate_max_tecu_per_h", e.ionosphere.vtec_rate_max_tecu_per_h, Bound::NonNegative);
  e.ionosphere.shell_height_km = i.number("shell_height_km", e.ionosphere.shell_height_km, Bound::Positive);
  i.finish();
}

void readReceiverClock(YamlSection c, ErrorModelConfig& e) {
  auto& r = e.receiver_clock;
  r.enabled = c.boolean("enabled", r.enabled);
  r.initial_sigma_s = c.number("initial_sigma_s", r.initial_sigma_s, Bound::NonNegative);
  r.random_walk_sigma_s = c.number("random_walk_sigma_s", r.random_walk_sigma_s, Bound::NonNegative);
  r.drift_sigma_s_per_s = c.number("drift_sigma_s_per_s", r.drift_sigma_s_per_s, Bound::NonNegative);
  r.step_s = c.number("step_s", r.step_s, Bound::NonNegative);
  r.steps_per_hour = c.number("steps_per_hour", r.steps_per_hour, Bound::NonNegative);
  r.galileo_offset_sigma_s = c.number("galileo_offset_sigma_s", r.galileo_offset_sigma_s, Bound::NonNegative);
  if (r.galileo_offset_sigma_s > 1e-3) c.fail("galileo_offset_sigma_s", "must be <= 1 ms");
  if (r.initial_sigma_s > 1e-3) c.fail("initial_sigma_s", "must be <= 1 ms");
  c.finish();
}

void readAmbiguity(YamlSection a, ErrorModelConfig& e) {
  e.ambiguity.enabled = a.boolean("enabled", e.ambiguity.enabled);
  e.ambiguity.max_abs_cycles = a.integer("max_abs_cycles", e.ambiguity.max_abs_cycles, 0);
  if (e.ambiguity.max_abs_cycles > 1000000) a.fail("max_abs_cycles", "must be <= 1000000");
  e.ambiguity.satellite_phase_biases = a.boolean("satellite_phase_biases", e.ambiguity.satellite_phase_biases);
  a.finish();
}

void readPhaseBreaks(YamlSection b, ErrorModelConfig& e) {
  e.phase_breaks.enabled = b.boolean("enabled", e.phase_breaks.enabled);
  e.phase_breaks.body_elevation_mask_rad =
      b.number("body_elevation_mask_deg", e.phase_breaks.body_elevation_mask_rad * kRadToDeg) * kDegToRad;
  e.phase_breaks.reacquisition_s = b.number("reacquisition_s", e.phase_breaks.reacquisition_s, Bound::NonNegative);
  b.finish();
}

void readProducts(YamlSection p, ErrorModelConfig& e) {
  using Model = ErrorModelConfig::ProductErrorModel;
  e.products.enabled = p.boolean("enabled", e.products.enabled);
  const std::string model = p.choice(
      "model", e.products.model == Model::AnalysisCentre ? "analysis_centre" : "independent",
      {"independent", "analysis_centre"});
  e.products.model = model == "analysis_centre" ? Model::AnalysisCentre : Model::Independent;
  e.products.orbit_sigma_m = p.number("orbit_sigma_m", e.products.orbit_sigma_m, Bound::NonNegative);
  e.products.clock_sigma_m = p.number("clock_sigma_m", e.products.clock_sigma_m, Bound::NonNegative);
  e.products.radial_sigma_m = p.number("radial_sigma_m", e.products.radial_sigma_m, Bound::NonNegative);
  e.products.along_sigma_m = p.number("along_sigma_m", e.products.along_sigma_m, Bound::NonNegative);
  e.products.cross_sigma_m = p.number("cross_sigma_m", e.products.cross_sigma_m, Bound::NonNegative);
  e.products.clock_residual_sigma_m =
      p.number("clock_residual_sigma_m", e.products.clock_residual_sigma_m, Bound::NonNegative);
  e.products.scale_half_range = p.number("scale_half_range", e.products.scale_half_range, Bound::NonNegative);
  p.finish();
}

void readErrors(YamlSection s, ErrorModelConfig& e) {
  readThermal(s.section("thermal"), e);
  readMultipath(s.section("multipath"), e);
  readTroposphere(s.section("troposphere"), e);
  readIonosphere(s.section("ionosphere"), e);
  readReceiverClock(s.section("receiver_clock"), e);
  readAmbiguity(s.section("ambiguity"), e);
  readPhaseBreaks(s.section("phase_breaks"), e);
  readProducts(s.section("products"), e);
  s.finish();
}

/// A list of numbers (finite, >= minimum) under `key`.
std::vector<double> numbers(YamlSection& s, const std::string& key, double minimum) {
  std::vector<double> out;
  for (const std::string& t : s.textList(key, {}, true)) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(v) || v < minimum)
      s.fail(key, "expected numbers >= " + format("%g", minimum) + ", got \"" + t + "\"");
    out.push_back(v);
  }
  return out;
}

/// observations.outages.keeps_lock: one flag per outage or one for all (default false).
std::vector<bool> keepsLockFlags(YamlSection& s, std::size_t outages) {
  std::vector<bool> out(outages, false);
  if (!s.has("keeps_lock")) return out;
  const std::vector<std::string> flags = s.textList("keeps_lock", {});
  if (flags.size() != 1 && flags.size() != outages)
    s.fail("keeps_lock", "needs one flag per outage or one for all (" + std::to_string(outages) + " outages, " +
                             std::to_string(flags.size()) + " flags)");
  for (std::size_t i = 0; i < outages; ++i) {
    const std::string& t = flags[flags.size() == 1 ? 0 : i];
    if (t != "true" && t != "false") s.fail("keeps_lock", "expected true or false, got \"" + t + "\"");
    out[i] = t == "true";
  }
  return out;
}

/// observations.outages: { start_s: [..], duration_s: [..], keeps_lock: [..] } of equal length.
void readOutages(YamlSection s, std::vector<SimulationConfig::Outage>& outages) {
  if (!s.has("start_s") && !s.has("duration_s")) {
    s.finish();
    return;
  }
  const std::vector<double> start = numbers(s, "start_s", 0.0);
  const std::vector<double> duration = numbers(s, "duration_s", 1e-3);
  if (start.size() != duration.size())
    s.fail("duration_s", "needs one duration per start (" + std::to_string(start.size()) + " starts, " +
                             std::to_string(duration.size()) + " durations)");
  const std::vector<bool> keeps_lock = keepsLockFlags(s, start.size());
  outages.clear();
  for (std::size_t i = 0; i < start.size(); ++i) outages.push_back({start[i], duration[i], keeps_lock[i]});
  s.finish();
}

/// The `imu` section: grade by its key name, rate 1..2000 Hz.
void readImu(YamlSection s, SimulationConfig::Imu& imu) {
  imu.enabled = s.boolean("enabled", imu.enabled);
  if (s.has("grade")) {
    const std::string g = s.text("grade", "");
    const std::optional<ImuGrade> grade = imuGradeFromName(g);
    if (!grade) s.fail("grade", "must be consumer_mems, industrial_mems or tactical, got \"" + g + "\"");
    imu.grade = *grade;
  }
  imu.rate_hz = s.number("rate_hz", imu.rate_hz, Bound::Positive);
  if (imu.rate_hz > 2000.0) s.fail("rate_hz", "must be <= 2000");
  imu.errors = s.boolean("errors", imu.errors);
  s.finish();
}

}  // namespace

SimulationConfig parseSimulationConfig(const std::string& yaml_text, const std::string& source_name,
                                       SimulationConfig c) {
  const YAML::Node root = parseYamlDocument(yaml_text, source_name);
  try {
    YamlSection top(root, source_name, "");
    {
      auto f = top.section("flight");
      c.rate_hz = f.number("rate_hz", c.rate_hz, Bound::Positive);
      if (c.rate_hz > 100.0) f.fail("rate_hz", "must be <= 100");
      if (f.has("duration_min")) {
        const double m = f.number("duration_min", 0.0, Bound::Positive);
        if (m > 24 * 60) f.fail("duration_min", "must be <= 1440");
        c.duration_s = m * 60.0;
      }
      if (f.has("start")) c.start = parseStart(f, "start", GnssTime());
      auto o = f.section("origin");
      const double lat = o.number("latitude_deg", c.origin.latitude_rad * kRadToDeg);
      const double lon = o.number("longitude_deg", c.origin.longitude_rad * kRadToDeg);
      const double h = o.number("height_m", c.origin.height_m);
      if (std::abs(lat) > 89.0) o.fail("latitude_deg", "must be within +-89");
      if (std::abs(h) > 20000.0) o.fail("height_m", "must be within +-20 km");
      c.origin = {lat * kDegToRad, lon * kDegToRad, h};
      o.finish();
      f.finish();
    }
    {
      auto k = top.section("constellation");
      c.satellites = k.integer("satellites", c.satellites, 24);
      if (c.satellites > 32) k.fail("satellites", "must be 24..32");
      if (k.has("systems")) {
        const std::string t = k.text("systems", "G");
        if (t == "G") c.systems = {GnssSystem::GPS};
        else if (t == "GE") c.systems = {GnssSystem::GPS, GnssSystem::Galileo};
        else k.fail("systems", "must be G or GE");
      }
      c.galileo_satellites = k.integer("galileo_satellites", c.galileo_satellites, 1);
      if (c.galileo_satellites > 36) k.fail("galileo_satellites", "must be 1..36");
      c.orbit_interval_s = k.number("orbit_interval_s", c.orbit_interval_s, Bound::Positive);
      c.clock_interval_s = k.number("clock_interval_s", c.clock_interval_s, Bound::Positive);
      k.finish();
    }
    {
      auto o = top.section("observations");
      c.elevation_mask_rad = o.number("elevation_mask_deg", c.elevation_mask_rad * kRadToDeg) * kDegToRad;
      c.loss_of_lock_flags = o.boolean("loss_of_lock_flags", c.loss_of_lock_flags);
      c.quantize = o.boolean("quantize", c.quantize);
      c.marker_name = o.text("marker_name", c.marker_name);
      if (c.marker_name.empty() || c.marker_name.size() > 60) o.fail("marker_name", "1..60 characters");
      readOutages(o.section("outages"), c.outages);
      o.finish();
    }
    readErrors(top.section("errors"), c.errors);
    readImu(top.section("imu"), c.imu);
    top.finish();
  } catch (const YAML::Exception& e) {
    throw ConfigError(source_name, "", std::string("YAML error: ") + e.what());
  }
  return c;
}

SimulationConfig loadSimulationConfig(const std::string& path, SimulationConfig base) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path, "", "cannot open the file");
  std::ostringstream os;
  os << in.rdbuf();
  if (in.bad()) throw ConfigError(path, "", "read error");
  return parseSimulationConfig(os.str(), path, std::move(base));
}

}  // namespace ppp
