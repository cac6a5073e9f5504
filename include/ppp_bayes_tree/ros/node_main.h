#pragma once
// runNode: the whole main() of every node of the package (ppp_ekf_node,
// ppp_smoother_node through runPppNode; ppp_stream_node through runStreamNode).
//
// Start-up errors (a bad parameter, a missing product file, a bad input spec)
// must reach the user. A ROS_FATAL written while the node's constructor unwinds
// is lost when the last NodeHandle goes and ros::shutdown() closes the log with
// it, so:
//  * a NodeHandle outlives the node object, keeping ROS and its log up while
//    the error is reported;
//  * the error is written to stderr as well as to the ROS log, always naming
//    the node, the key path or file, and the reason;
//  * a node started before the master says, at once on stderr, which master
//    URI it is waiting for (roscpp itself waits silently).
#include <functional>
#include <string>

namespace ros {
class NodeHandle;
}

namespace ppp_ros {

/// Initialises ROS as `node_name`, then calls `run(nh)` (construct the node on `nh`
/// and its private handle ros::NodeHandle("~"), then spin until shutdown). Returns
/// the process exit code: 0 after a normal shutdown, 1 when `run` threw (the node
/// could not start: "<node_name>: cannot start: <reason>" on stderr and in the ROS log).
int runNode(int argc, char** argv, const std::string& node_name, const std::function<void(ros::NodeHandle&)>& run);

/// runNode for the PPP node with `estimator` ("ekf" or "smoother").
int runPppNode(int argc, char** argv, const std::string& node_name, const std::string& estimator);

}  // namespace ppp_ros
