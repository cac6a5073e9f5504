#pragma once
// Strict binding of the model sections of config/ppp.yaml (YamlSection: every
// key known, types and ranges checked, errors name the file and key path):
//   measurement_model:          -> MeasurementModelOptions
//     signals:                  -> SignalSelectionOptions (systems, code/phase priorities)
//   cycle_slip:                 -> CycleSlipOptions
// config/ppp.yaml documents every key with its meaning, unit and default.
// Absent keys keep the defaults of the option structs.
#include <yaml-cpp/yaml.h>

#include <string>

#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/ppp/model/arc_tracker.h"
#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"

namespace ppp {

/// Binds the `measurement_model` mapping (`node`, may be null/empty) into
/// `model` and its `signals` sub-mapping into `signals`. Throws ConfigError.
void bindMeasurementModelOptions(const YAML::Node& node, const std::string& file, MeasurementModelOptions& model,
                                 SignalSelectionOptions& signals);
/// Binds the `cycle_slip` mapping. Throws ConfigError.
void bindCycleSlipOptions(const YAML::Node& node, const std::string& file, CycleSlipOptions& options);

/// Names used in the YAML file.
std::string toString(DryTroposphereModel model);  // "modified_hopfield" | "saastamoinen"
std::string toString(TroposphereMapping mapping);  // "modified_hopfield" | "niell" | "gmf"

}  // namespace ppp
