#include "ppp_bayes_tree/ros/node_config.h"

#include <ros/node_handle.h>

#include "ppp_bayes_tree/ppp/config/yaml_document.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"

namespace ppp_ros {

namespace {

/// The parameter naming the YAML files a launch loaded into the namespace.
constexpr const char* kConfigFilesKey = "config_files";

/// Reads again each file `config_files` names (ppp::loadYamlDocument: a key
/// written twice in one mapping, or a syntax error, is a ConfigError naming the
/// file and line) and takes the key out of the document to bind. The parameter
/// server keeps only the last of a key `rosparam load` saw twice, so the file is
/// the only place where the first one is still visible.
void checkConfigFiles(YAML::Node& root, const std::string& source) {
  const YAML::Node files = static_cast<const YAML::Node&>(root)[kConfigFilesKey];
  if (!files) return;
  if (!files.IsSequence()) throw ppp::ConfigError(source, kConfigFilesKey, "expected a list of YAML file paths");
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (!files[i].IsScalar())
      throw ppp::ConfigError(source, std::string(kConfigFilesKey) + "[" + std::to_string(i) + "]", "expected a file path");
    ppp::loadYamlDocument(files[i].as<std::string>());
  }
  root.remove(kConfigFilesKey);
}

/// The estimator the node runs: its own, or ros.estimator when that is registered
/// and gives the same solutions (the EKF node: ekf or ekf_ins; the smoother node: smoother or smoother_ins).
std::string chosenEstimator(const std::string& own, const std::string& configured, const std::string& source) {
  if (configured.empty() || own.empty()) return configured.empty() ? own : configured;
  const ppp::EstimatorEntry* chosen = ppp::findEstimator(configured);
  const ppp::EstimatorEntry* node = ppp::findEstimator(own);
  if (!chosen) throw ppp::ConfigError(source, "ros.estimator", "\"" + configured + "\" is not a registered estimator");
  if (node && chosen->solutions != node->solutions)
    throw ppp::ConfigError(source, "ros.estimator",
                           "\"" + configured + "\" does not give the solutions of the " + own + " node (another node runs it)");
  return configured;
}

}  // namespace

NodeConfig bindNodeConfig(const YAML::Node& root, const std::string& source_name, const std::string& estimator) {
  NodeConfig c;
  c.ppp = ppp::bindPppConfig(root, source_name);
  c.ros = bindRosNodeOptions(c.ppp.ros, source_name);
  c.ros.node_estimator = estimator.empty() ? c.ros.estimator : estimator;
  if (!estimator.empty() || !c.ros.configured_estimator.empty())
    c.ros.estimator = chosenEstimator(estimator, c.ros.configured_estimator, source_name);
  c.ros.live_input.fallback = c.ppp.ssr.fallback;  // one broadcast fallback rule, offline and live
  if (c.ros.imu.start_attitude == ImuStartAttitude::AlignInMotion && c.ros.estimator == "smoother_ins")
    throw ppp::ConfigError(source_name, "ros.imu.initial_attitude",
                           "align_in_motion: smoother_ins has no heading alignment in motion (give the start: "
                           "given or level_at_rest with initial_rpy_deg)");
  return c;
}

NodeConfig loadNodeConfig(const ros::NodeHandle& private_nh, const std::string& estimator) {
  const std::string source = "ROS parameters " + private_nh.getNamespace();
  XmlRpc::XmlRpcValue params;
  YAML::Node root(YAML::NodeType::Map);
  if (private_nh.getParam(private_nh.getNamespace(), params) && params.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    root = xmlRpcToYaml(params);
  checkConfigFiles(root, source);
  return bindNodeConfig(root, source, estimator);
}

}  // namespace ppp_ros
