#include "ppp_bayes_tree/ros/node_main.h"

#include <ros/ros.h>

#include <iostream>

#include "ppp_bayes_tree/io/transport/credential_mask.h"
#include "ppp_bayes_tree/ros/ppp_node.h"

namespace ppp_ros {

int runNode(int argc, char** argv, const std::string& node_name, const std::function<void(ros::NodeHandle&)>& run) {
  ros::init(argc, argv, node_name);
  if (!ros::master::check()) {
    std::cerr << node_name << ": waiting for the ROS master at " << ros::master::getURI()
              << " (start roscore, or set ROS_MASTER_URI)" << std::endl;
  }
  ros::NodeHandle keep_ros_up;  // outlives the node: the log stays open while a start-up error unwinds
  try {
    run(keep_ros_up);
  } catch (const std::exception& e) {
    // Masked: a start-up error may quote an input spec (and its password) however mistyped.
    const std::string text = ppp::maskCredentials(node_name + ": cannot start: " + e.what());
    std::cerr << text << std::endl;
    ROS_FATAL_STREAM(text);
    return 1;
  }
  return 0;
}

int runPppNode(int argc, char** argv, const std::string& node_name, const std::string& estimator) {
  return runNode(argc, argv, node_name, [&](ros::NodeHandle& nh) {
    PppNode node(nh, ros::NodeHandle("~"), estimator);
    ros::spin();
  });
}

}  // namespace ppp_ros
