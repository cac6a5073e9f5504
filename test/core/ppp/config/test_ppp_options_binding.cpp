// Binding of the measurement_model (+ signals) and cycle_slip sections of
// config/ppp.yaml: defaults, every key of each section, and errors naming the
// key path for unknown keys, wrong types and out-of-range values.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

ConfigError errorOf(const std::string& yaml) {
  try {
    parsePppConfig(yaml, "bad.yaml");
  } catch (const ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "no ConfigError for:\n" << yaml;
  return ConfigError("", "", "");
}

TEST(PppOptionsBinding, EmptySectionsKeepTheStructDefaults) {
  const PppConfig c = parsePppConfig("measurement_model: {}\ncycle_slip:\n", "empty.yaml");
  const MeasurementModelOptions m;
  EXPECT_EQ(c.model.elevation_cutoff_rad, m.elevation_cutoff_rad);
  EXPECT_EQ(c.model.phase_sigma_zenith_m, m.phase_sigma_zenith_m);
  EXPECT_EQ(c.model.code_phase_ratio, m.code_phase_ratio);
  EXPECT_EQ(c.model.mapping, m.mapping);
  EXPECT_EQ(c.model.dry_troposphere, m.dry_troposphere);
  EXPECT_TRUE(c.model.solid_earth_tide && c.model.ocean_loading && c.model.phase_windup && c.model.shapiro &&
              c.model.satellite_antenna && c.model.receiver_antenna == ReceiverAntennaPolicy::Warn && c.model.exclude_eclipse);
  EXPECT_EQ(c.model.yaw_manoeuvre, YawManoeuvreHandling::Model);
  const SignalSelectionOptions s;
  EXPECT_EQ(c.signals.systems, s.systems);
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].code1_attributes, s.priorities[GnssSystem::GPS].code1_attributes);
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].code2_attributes, s.priorities[GnssSystem::GPS].code2_attributes);
  EXPECT_EQ(c.signals.priorities[GnssSystem::Galileo].phase2_attributes, s.priorities[GnssSystem::Galileo].phase2_attributes);
  EXPECT_TRUE(c.signals.require_code_osb);
  const CycleSlipOptions k;
  EXPECT_EQ(c.cycle_slip_options.mw_sigma_factor, k.mw_sigma_factor);
  EXPECT_EQ(c.cycle_slip_options.gf_threshold_base_m, k.gf_threshold_base_m);
  EXPECT_FALSE(c.cycle_slip_options.max_gap_s.has_value());
  EXPECT_EQ(c.cycle_slip_options.max_gap_intervals, k.max_gap_intervals);
}

TEST(PppOptionsBinding, EveryMeasurementModelKeyIsBound) {
  const PppConfig c = parsePppConfig(R"(
measurement_model:
  elevation_cutoff_deg: 10
  phase_sigma_zenith_m: 0.004
  code_phase_ratio: 150
  scale_sigma_for_ionosphere_free: false
  troposphere: {dry_model: saastamoinen, mapping: modified_hopfield}
  corrections:
    solid_earth_tide: false
    ocean_loading: false
    phase_windup: false
    satellite_antenna: false
    receiver_antenna: false
    shapiro: false
    exclude_eclipse: false
    yaw_manoeuvre: nominal
  signals:
    systems: [Galileo, GPS]
    require_code_osb: false
    phase_shift: restore_original
    gps: {code1: [C], code2: [L, W], phase1: [W, C], phase2: [X]}
    galileo: {code1: [X], code2: [X, Q], phase1: [X], phase2: [X]}
)", "m.yaml");
  EXPECT_NEAR(c.model.elevation_cutoff_rad, 10.0 * kDegToRad, 1e-15);
  EXPECT_EQ(c.model.phase_sigma_zenith_m, 0.004);
  EXPECT_EQ(c.model.code_phase_ratio, 150.0);
  EXPECT_FALSE(c.model.scale_sigma_for_ionosphere_free);
  EXPECT_EQ(c.model.dry_troposphere, DryTroposphereModel::Saastamoinen);
  EXPECT_EQ(c.model.mapping, TroposphereMapping::ModifiedHopfield);  // the default is gmf
  EXPECT_FALSE(c.model.solid_earth_tide || c.model.ocean_loading || c.model.phase_windup || c.model.shapiro ||
               c.model.satellite_antenna || c.model.receiver_antenna != ReceiverAntennaPolicy::Off || c.model.exclude_eclipse);
  EXPECT_EQ(c.model.yaw_manoeuvre, YawManoeuvreHandling::Nominal);
  EXPECT_EQ(parsePppConfig("measurement_model: {corrections: {yaw_manoeuvre: exclude}}\n", "y.yaml").model.yaw_manoeuvre,
            YawManoeuvreHandling::Exclude);
  EXPECT_EQ(c.signals.systems, (std::vector<GnssSystem>{GnssSystem::Galileo, GnssSystem::GPS}));
  EXPECT_FALSE(c.signals.require_code_osb);
  EXPECT_EQ(c.signals.phase_shift, PhaseShiftHandling::RestoreOriginal);
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].code1_attributes, std::vector<char>{'C'});
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].code2_attributes, (std::vector<char>{'L', 'W'}));
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].phase1_attributes, (std::vector<char>{'W', 'C'}));
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].phase2_attributes, std::vector<char>{'X'});  // a list of one
  EXPECT_EQ(c.signals.priorities[GnssSystem::Galileo].code2_attributes, (std::vector<char>{'X', 'Q'}));
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].band1, '1');  // bands are not configurable
  EXPECT_EQ(c.signals.priorities[GnssSystem::Galileo].band2, '5');
  const PppConfig n = parsePppConfig("measurement_model: {troposphere: {mapping: niell}}\n", "n.yaml");
  EXPECT_EQ(n.model.mapping, TroposphereMapping::Niell);
}

TEST(PppOptionsBinding, GlonassIsListedByNameOrLetterWithItsPriorities) {
  const PppConfig c = parsePppConfig(R"(
measurement_model:
  signals:
    systems: [GPS, Galileo, GLONASS]
    glonass: {code1: [C], code2: [C, P], phase1: [C], phase2: [C], code_sigma_factor: 5}
)", "g.yaml");
  EXPECT_FALSE(c.signals.systems_from_products);
  EXPECT_EQ(c.signals.systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::Galileo, GnssSystem::GLONASS}));
  const SystemSignalPriority& r = c.signals.priorities[GnssSystem::GLONASS];
  EXPECT_EQ(r.code1_attributes, std::vector<char>{'C'});
  EXPECT_EQ(r.code2_attributes, (std::vector<char>{'C', 'P'}));
  EXPECT_EQ(r.phase2_attributes, std::vector<char>{'C'});
  EXPECT_EQ(r.code_sigma_factor, 5.0);
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].code_sigma_factor, 1.0);  // the others keep theirs
  const PppConfig letter = parsePppConfig("measurement_model: {signals: {systems: [G, R]}}\n", "r.yaml");
  EXPECT_EQ(letter.signals.systems, (std::vector<GnssSystem>{GnssSystem::GPS, GnssSystem::GLONASS}));
  const PppConfig defaults = parsePppConfig("measurement_model: {signals: {systems: auto}}\n", "a.yaml");
  EXPECT_EQ(defaults.signals.priorities[GnssSystem::GLONASS].code_sigma_factor,
            signalTableRow(GnssSystem::GLONASS)->priority.code_sigma_factor);
}

TEST(PppOptionsBinding, EveryCycleSlipKeyIsBound) {
  const PppConfig c = parsePppConfig(R"(
cycle_slip:
  melbourne_wuebbena: {sigma_factor: 4, min_threshold_cycles: 1.5, initial_sigma_cycles: 0.7, min_samples: 8, window: 30}
  geometry_free:
    threshold_base_m: 0.04
    threshold_rate_m_per_s: 0.001
    threshold_max_m: 0.2
    fit_points: 6
    drift_allowance_m_per_s: 0.003
    sigma_factor: 3.5
    min_samples: 7
  max_gap_s: 75
  max_gap_intervals: 2.5
  default_interval_s: 1
  use_loss_of_lock: false
)", "c.yaml");
  const CycleSlipOptions& o = c.cycle_slip_options;
  EXPECT_EQ(o.mw_sigma_factor, 4.0);
  EXPECT_EQ(o.mw_min_threshold_cycles, 1.5);
  EXPECT_EQ(o.mw_initial_sigma_cycles, 0.7);
  EXPECT_EQ(o.mw_min_samples, 8);
  EXPECT_EQ(o.mw_window, 30);
  EXPECT_EQ(o.gf_threshold_base_m, 0.04);
  EXPECT_EQ(o.gf_threshold_rate_mps, 0.001);
  EXPECT_EQ(o.gf_threshold_max_m, 0.2);
  EXPECT_EQ(o.gf_fit_points, 6);
  EXPECT_EQ(o.gf_drift_allowance_mps, 0.003);
  EXPECT_EQ(o.gf_sigma_factor, 3.5);
  EXPECT_EQ(o.gf_min_samples, 7);
  ASSERT_TRUE(o.max_gap_s.has_value());
  EXPECT_EQ(*o.max_gap_s, 75.0);
  EXPECT_EQ(o.max_gap_intervals, 2.5);
  EXPECT_EQ(o.default_interval_s, 1.0);
  EXPECT_FALSE(o.use_loss_of_lock);
  EXPECT_FALSE(parsePppConfig("cycle_slip: {max_gap_s: auto}\n", "a.yaml").cycle_slip_options.max_gap_s);
}

TEST(PppOptionsBinding, ErrorsNameTheKeyPath) {
  struct Case {
    const char* yaml;
    const char* key_path;
    const char* reason_part;
  };
  const Case cases[] = {
      {"measurement_model: {cutoff: 7}\n", "measurement_model.cutoff", "unknown key"},
      {"measurement_model: {elevation_cutoff_deg: high}\n", "measurement_model.elevation_cutoff_deg",
       "expected a number"},
      {"measurement_model: {elevation_cutoff_deg: 95}\n", "measurement_model.elevation_cutoff_deg", "below 90"},
      {"measurement_model: {phase_sigma_zenith_m: 0}\n", "measurement_model.phase_sigma_zenith_m", "must be > 0"},
      {"measurement_model: {troposphere: {mapping: vmf3}}\n", "measurement_model.troposphere.mapping",
       "expected one of gmf modified_hopfield niell"},
      {"measurement_model: {troposphere: {wet: 1}}\n", "measurement_model.troposphere.wet", "unknown key"},
      {"measurement_model: {corrections: {shapiro: 2}}\n", "measurement_model.corrections.shapiro",
       "expected true or false"},
      {"measurement_model: {corrections: {iono: true}}\n", "measurement_model.corrections.iono", "unknown key"},
      {"measurement_model: {signals: {systems: [GPS, QZSS]}}\n", "measurement_model.signals.systems",
       "expected GPS, GLONASS, Galileo or BeiDou"},
      {"measurement_model: {signals: {glonass: {code_sigma_factor: 0}}}\n",
       "measurement_model.signals.glonass.code_sigma_factor", "must be > 0"},
      {"measurement_model: {signals: {systems: [GPS, G]}}\n", "measurement_model.signals.systems", "given twice"},
      {"measurement_model: {signals: {systems: []}}\n", "measurement_model.signals.systems", "must not be empty"},
      {"measurement_model: {signals: {gps: {code1: [WC]}}}\n", "measurement_model.signals.gps.code1",
       "tracking-mode letters"},
      {"measurement_model: {signals: {gps: {code1: {W: 1}}}}\n", "measurement_model.signals.gps.code1",
       "expected a list"},
      {"measurement_model: {signals: {gps: {code3: [W]}}}\n", "measurement_model.signals.gps.code3", "unknown key"},
      {"measurement_model: {signals: {phase_shift: ignore}}\n", "measurement_model.signals.phase_shift",
       "expected one of"},
      {"measurement_model: {signals: 1}\n", "measurement_model.signals", "expected a mapping"},
      {"cycle_slip: {mw_sigma_factor: 4}\n", "cycle_slip.mw_sigma_factor", "unknown key"},
      {"cycle_slip: {melbourne_wuebbena: {window: 0}}\n", "cycle_slip.melbourne_wuebbena.window", "must be >= 1"},
      {"cycle_slip: {melbourne_wuebbena: {min_samples: 2.5}}\n", "cycle_slip.melbourne_wuebbena.min_samples",
       "expected an integer"},
      {"cycle_slip: {geometry_free: {fit_points: 1}}\n", "cycle_slip.geometry_free.fit_points", "must be >= 2"},
      {"cycle_slip: {geometry_free: {threshold_max_m: 0.01}}\n", "cycle_slip.geometry_free.threshold_max_m",
       "threshold_base_m"},
      {"cycle_slip: {max_gap_s: soon}\n", "cycle_slip.max_gap_s", "expected a number"},
      {"cycle_slip: {max_gap_s: -5}\n", "cycle_slip.max_gap_s", "must be > 0"},
      {"cycle_slip: {use_loss_of_lock: sometimes}\n", "cycle_slip.use_loss_of_lock", "expected true or false"},
      // Strict types: quoted text is never a number or a bool, YAML 1.1
      // yes/no/on/off are not bools, and a list is never a lone value.
      {"measurement_model: {elevation_cutoff_deg: \"7\"}\n", "measurement_model.elevation_cutoff_deg",
       "expected a number, got the text \"7\" (quoted"},
      {"measurement_model: {elevation_cutoff_deg: '7'}\n", "measurement_model.elevation_cutoff_deg",
       "expected a number"},
      {"cycle_slip: {melbourne_wuebbena: {window: \"60\"}}\n", "cycle_slip.melbourne_wuebbena.window",
       "expected an integer, got the text \"60\" (quoted"},
      {"cycle_slip: {max_gap_s: \"30\"}\n", "cycle_slip.max_gap_s", "expected a number"},
      {"measurement_model: {corrections: {shapiro: \"yes\"}}\n", "measurement_model.corrections.shapiro",
       "expected true or false, got the text \"yes\" (quoted"},
      {"measurement_model: {corrections: {shapiro: yes}}\n", "measurement_model.corrections.shapiro",
       "expected true or false, got 'yes'"},
      {"measurement_model: {corrections: {shapiro: off}}\n", "measurement_model.corrections.shapiro",
       "expected true or false"},
      {"measurement_model: {corrections: {shapiro: \"true\"}}\n", "measurement_model.corrections.shapiro",
       "expected true or false"},
      {"measurement_model: {signals: {systems: GPS}}\n", "measurement_model.signals.systems",
       "expected a list [a, b, ...], got the single value 'GPS' (a list of one is [GPS])"},
      {"measurement_model: {signals: {gps: {code1: W}}}\n", "measurement_model.signals.gps.code1", "expected a list"},
  };
  for (const auto& c : cases) {
    const ConfigError e = errorOf(c.yaml);
    EXPECT_EQ(e.file(), "bad.yaml") << c.yaml;
    EXPECT_EQ(e.keyPath(), c.key_path) << c.yaml << " -> " << e.what();
    EXPECT_NE(e.reason().find(c.reason_part), std::string::npos) << c.yaml << " -> " << e.what();
  }
}

TEST(PppOptionsBinding, TemplateRestatesTheModelDefaults) {
  const PppConfig c = loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp.yaml");
  const MeasurementModelOptions m;
  EXPECT_NEAR(c.model.elevation_cutoff_rad, m.elevation_cutoff_rad, 1e-15);
  EXPECT_EQ(c.model.mapping, m.mapping);
  EXPECT_EQ(c.model.code_phase_ratio, m.code_phase_ratio);
  const SignalSelectionOptions s;
  EXPECT_EQ(c.signals.systems, s.systems);
  EXPECT_EQ(c.signals.priorities[GnssSystem::GPS].code2_attributes, s.priorities[GnssSystem::GPS].code2_attributes);
  EXPECT_EQ(c.signals.priorities[GnssSystem::Galileo].code1_attributes, s.priorities[GnssSystem::Galileo].code1_attributes);
  EXPECT_EQ(c.signals.priorities[GnssSystem::GLONASS].code1_attributes, s.priorities[GnssSystem::GLONASS].code1_attributes);
  EXPECT_EQ(c.signals.priorities[GnssSystem::GLONASS].code_sigma_factor, s.priorities[GnssSystem::GLONASS].code_sigma_factor);
  const CycleSlipOptions k;
  EXPECT_EQ(c.cycle_slip_options.gf_threshold_rate_mps, k.gf_threshold_rate_mps);
  EXPECT_EQ(c.cycle_slip_options.mw_window, k.mw_window);
  EXPECT_FALSE(c.cycle_slip_options.max_gap_s.has_value());
}

TEST(PppOptionsBinding, RealDataConfigOverridesOnlyItsKeys) {
  // config/ppp_real_data.yaml sets nothing now: its 30 m start prior and GMF are the defaults.
  const PppConfig c = loadPppConfig(std::string(PPP_REPO_DIR) + "/config/ppp_real_data.yaml");
  const PppConfig d;
  EXPECT_EQ(c.stochastic.position.initial_sigma_m, 30.0);
  EXPECT_EQ(c.model.mapping, TroposphereMapping::Gmf);
  EXPECT_EQ(c.stochastic.position.process_noise_m_per_sqrt_s, d.stochastic.position.process_noise_m_per_sqrt_s);
  EXPECT_EQ(c.stochastic.zwd.initial_sigma_m, d.stochastic.zwd.initial_sigma_m);
  EXPECT_EQ(c.model.code_phase_ratio, d.model.code_phase_ratio);
  EXPECT_EQ(c.model.elevation_cutoff_rad, d.model.elevation_cutoff_rad);
}

}  // namespace
}  // namespace ppp
