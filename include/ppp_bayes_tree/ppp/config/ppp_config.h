#pragma once
// PppConfig: the whole PPP configuration (config/ppp.yaml documents every key):
//   stochastic:        a priori sigmas and process noise (StochasticModel)
//   estimator:         EKF options (EkfOptions), with `start:` the code least squares
//   smoother:          PPP smoother options (PppSmootherOptions; its screening values
//                      are copied from `estimator`)
//   measurement_model: MeasurementModelOptions, with `signals:` the SignalSelectionOptions
//   cycle_slip:        CycleSlipOptions (arc tracker)
//   ssr:               SsrStreamOptions (broadcast + SSR orbits and clocks, ppp_solve --nav --ssr,
//                      the nodes' live SSR feed): age limits, the stream's antenna model and
//                      the broadcast fallback
//   ambiguity_resolution: AmbiguityResolutionOptions (PPP-AR: wide lane, LAMBDA)
//   ros:               the ROS nodes' section (kept raw, bound by the node)
// (bound by ppp_options_binding.h; the raw nodes are kept as well)
// Loading is strict: an unknown key, a key given twice in one mapping, a wrong
// type (a quoted "7" for a number, yes/"true" for a bool, a single value for a
// list) or an out-of-range value throws ConfigError naming the file, the key path
// (or the line) and the reason. Absent keys keep their defaults: the values for
// real receiver data (config/ppp.yaml). The method's table is the
// preset config/method_table.yaml = methodTablePppConfig().
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "ppp_bayes_tree/models/broadcast_fallback.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"
#include "ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h"
#include "ppp_bayes_tree/ppp/config/ppp_options_binding.h"
#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/ppp/estimators/code_least_squares.h"
#include "ppp_bayes_tree/ppp/estimators/ekf_options.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_options.h"
#include "ppp_bayes_tree/ppp/estimators/smoother_options.h"
#include "ppp_bayes_tree/ppp/model/stochastic_model.h"

namespace ppp {

/// `ssr:` the age limits, and the satellite antenna model of the SSR stream's
/// orbits and clocks (RTCM SSR carries none; its provider states it, e.g. IGS20 for
/// the IGS SSR streams, IGS14 for a stream made by ppp_ssr_encode from GRG products).
/// Empty: not known (ambiguity_resolution.enabled: auto then stays float).
/// `fallback`: the broadcast fallback of both the offline run (ppp_solve --nav
/// --ssr) and the live SSR feed (models/broadcast_fallback.h).
struct SsrStreamOptions : SsrAgeLimits {
  std::string antenna_model;
  BroadcastFallbackOptions fallback;
};

struct PppConfig {
  StochasticModel stochastic;
  EkfOptions estimator;
  CodeLeastSquaresOptions start;
  PppSmootherOptions smoother;
  MeasurementModelOptions model;
  SignalSelectionOptions signals;
  CycleSlipOptions cycle_slip_options;
  SsrStreamOptions ssr;
  AmbiguityResolutionOptions ambiguity_resolution;  // `ambiguity_resolution:` (PPP-AR)
  /// The GNSS/INS filter's options (ppp_solve --imu-grade, --lever-arm; no YAML section).
  InsEkfOptions ins;
  /// The raw sections as written (already bound into the three members above).
  YAML::Node measurement_model = YAML::Node(YAML::NodeType::Map);
  YAML::Node cycle_slip = YAML::Node(YAML::NodeType::Map);
  /// `ros:` the ROS nodes' own section (topics, frames, products, latency),
  /// kept as written: the core does not read it, the ROS adapter binds it as
  /// strictly (ppp_bayes_tree/ros/node_options.h).
  YAML::Node ros = YAML::Node(YAML::NodeType::Map);
  std::string source_name = "<defaults>";  // the file it came from (for later error messages)

  /// What an estimator is built from (EstimatorOptions: stochastic, estimator,
  /// start, smoother, signals.systems, ambiguity_resolution, ins). Implicit, so that an
  /// estimator is made from the whole configuration as from its own options
  /// (makeEstimator(name, config, &why)).
  operator EstimatorOptions() const;
};

/// The method's configuration (config/method_table.yaml): the defaults with the
/// method's stochastic model (methodTableStochasticModel: position a priori 1 m),
/// its modified Hopfield mapping and no tropospheric gradients.
/// config/method_table.yaml loads to it.
PppConfig methodTablePppConfig();

/// Bind a YAML document (a mapping, or null for an empty one) on top of the
/// defaults; `source_name` names it in errors. The ROS nodes pass their
/// parameters here (typed by XmlRpc; strings carry the quoted-scalar tag "!").
/// Throws ConfigError.
PppConfig bindPppConfig(const YAML::Node& root, const std::string& source_name);
/// Parse YAML text; `source_name` names it in errors. A key given twice in one
/// mapping is an error naming both lines. Throws ConfigError.
PppConfig parsePppConfig(const std::string& yaml_text, const std::string& source_name);
/// Load a YAML file. Throws ConfigError (also when the file cannot be read).
PppConfig loadPppConfig(const std::string& path);
/// Load YAML files laid one on another in order, as the nodes' parameters are
/// (config/ppp.yaml, then overrides such as config/live.yaml): a later file's
/// mappings merge key by key into the earlier ones', its scalars and sequences
/// replace theirs. Syntax and duplicate keys are checked per file (errors name
/// the file); errors of the merged values name "a.yaml + b.yaml". No file: the
/// defaults. Throws ConfigError.
PppConfig loadPppConfig(const std::vector<std::string>& paths);

}  // namespace ppp
