// ppp_ekf_node: the forward EKF-PPP estimator as a ROS node (see ros/ppp_node.h).
#include <ros/ros.h>

#include "ppp_bayes_tree/ros/ppp_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "ppp_ekf_node");
  try {
    ppp_ros::PppNode node(ros::NodeHandle(), ros::NodeHandle("~"), "ekf");
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("ppp_ekf_node: cannot start: " << e.what());
    return 1;
  }
  return 0;
}
