#pragma once
// The PPP node's configuration (ppp_node.h): the whole private namespace (~) is
// one config/ppp.yaml document, the core sections bound by the core loader
// (ppp::bindPppConfig, strict) and `ros:` by bindRosNodeOptions. What both
// parts share is taken from the core section: the broadcast fallback of the
// live input is the `ssr:` one, the rule of ppp_solve --nav --ssr as well
// (models/broadcast_fallback.h).
#include <string>

#include <yaml-cpp/yaml.h>

#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ros/node_options.h"

namespace ros {
class NodeHandle;
}

namespace ppp_ros {

struct NodeConfig {
  ppp::PppConfig ppp;
  RosNodeOptions ros;
};

/// Binds a configuration document (the private namespace as YAML) for the node of
/// `estimator` ("" keeps RosNodeOptions' default). Throws ppp::ConfigError with the key path.
NodeConfig bindNodeConfig(const YAML::Node& root, const std::string& source_name, const std::string& estimator = "");

/// The private namespace of a running node through bindNodeConfig (the XmlRpc
/// types kept: no text round trip). `config_files` (a list of paths, set by the
/// launch files) names the YAML files loaded into the namespace: each is read
/// again and a key written twice in it is refused with its file and line.
/// Throws ppp::ConfigError.
NodeConfig loadNodeConfig(const ros::NodeHandle& private_nh, const std::string& estimator = "");

}  // namespace ppp_ros
