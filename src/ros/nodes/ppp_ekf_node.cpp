// ppp_ekf_node: the forward EKF-PPP estimator as a ROS node (see ros/ppp_node.h;
// start-up and error reporting: ros/node_main.h).
#include "ppp_bayes_tree/ros/node_main.h"

int main(int argc, char** argv) { return ppp_ros::runPppNode(argc, argv, "ppp_ekf_node", "ekf"); }
