// ppp_smoother_node: the PPP smoother (iSAM2 on the Bayes tree) as a ROS node; also
// ppp/odometry/smoothed and ppp/path/smoothed (see ros/ppp_node.h; start-up and
// error reporting: ros/node_main.h).
#include "ppp_bayes_tree/ros/node_main.h"

int main(int argc, char** argv) { return ppp_ros::runPppNode(argc, argv, "ppp_smoother_node", "smoother"); }
