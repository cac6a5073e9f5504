#include "ppp_bayes_tree/ros/node_config.h"

#include <ros/node_handle.h>

namespace ppp_ros {

NodeConfig bindNodeConfig(const YAML::Node& root, const std::string& source_name, const std::string& estimator) {
  NodeConfig c;
  c.ppp = ppp::bindPppConfig(root, source_name);
  c.ros = bindRosNodeOptions(c.ppp.ros, source_name);
  if (!estimator.empty()) c.ros.estimator = estimator;
  c.ros.live_input.fallback = c.ppp.ssr.fallback;  // one broadcast fallback rule, offline and live
  return c;
}

NodeConfig loadNodeConfig(const ros::NodeHandle& private_nh, const std::string& estimator) {
  const std::string source = "ROS parameters " + private_nh.getNamespace();
  XmlRpc::XmlRpcValue params;
  YAML::Node root(YAML::NodeType::Map);
  if (private_nh.getParam(private_nh.getNamespace(), params) && params.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    root = xmlRpcToYaml(params);
  return bindNodeConfig(root, source, estimator);
}

}  // namespace ppp_ros
