// ppp_smoother_node: the PPP smoother (iSAM2 on the Bayes tree) as a ROS node; also
// ppp/odometry/smoothed and ppp/path/smoothed (see ros/ppp_node.h).
#include <ros/ros.h>

#include "ppp_bayes_tree/ros/ppp_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "ppp_smoother_node");
  try {
    ppp_ros::PppNode node(ros::NodeHandle(), ros::NodeHandle("~"), "smoother");
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("ppp_smoother_node: cannot start: " << e.what());
    return 1;
  }
  return 0;
}
