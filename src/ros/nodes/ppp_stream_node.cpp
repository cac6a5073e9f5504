// ppp_stream_node: a serial port, TCP server, NTRIP caster or file replay as
// ROS topics (see ros/stream_node.h; parameters: config/stream.yaml).
#include "ppp_bayes_tree/ros/stream_node.h"

int main(int argc, char** argv) { return ppp_ros::runStreamNode(argc, argv, "ppp_stream_node"); }
