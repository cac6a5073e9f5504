#pragma once
// runPppNode: the whole main() of ppp_ekf_node and ppp_smoother_node.
//
// Start-up errors (a bad parameter, a missing product file) must reach the
// user. A ROS_FATAL written while the node's constructor unwinds is lost when
// the last NodeHandle goes and ros::shutdown() closes the log with it, so:
//  * a NodeHandle outlives the node object, keeping ROS and its log up while
//    the error is reported;
//  * the error is written to stderr as well as to the ROS log, always naming
//    the node, the key path or file, and the reason;
//  * a node started before the master says, at once on stderr, which master
//    URI it is waiting for (roscpp itself waits silently).
#include <string>

namespace ppp_ros {

/// Runs the PPP node with `estimator` ("ekf" or "smoother") until shutdown.
/// Returns the process exit code: 0 after a normal shutdown, 1 when the node
/// could not start (the reason printed on stderr and in the ROS log).
int runPppNode(int argc, char** argv, const std::string& node_name, const std::string& estimator);

}  // namespace ppp_ros
