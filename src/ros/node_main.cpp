#include "ppp_bayes_tree/ros/node_main.h"

#include <ros/ros.h>

#include <iostream>

#include "ppp_bayes_tree/ros/ppp_node.h"

namespace ppp_ros {

int runPppNode(int argc, char** argv, const std::string& node_name, const std::string& estimator) {
  ros::init(argc, argv, node_name);
  if (!ros::master::check()) {
    std::cerr << node_name << ": waiting for the ROS master at " << ros::master::getURI()
              << " (start roscore, or set ROS_MASTER_URI)" << std::endl;
  }
  ros::NodeHandle keep_ros_up;  // outlives the node: the log stays open while a start-up error unwinds
  try {
    PppNode node(keep_ros_up, ros::NodeHandle("~"), estimator);
    ros::spin();
  } catch (const std::exception& e) {
    const std::string text = node_name + ": cannot start: " + e.what();
    std::cerr << text << std::endl;
    ROS_FATAL_STREAM(text);
    return 1;
  }
  return 0;
}

}  // namespace ppp_ros
