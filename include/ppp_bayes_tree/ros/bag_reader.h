#pragma once
// Reading bags for the offline tools (ppp_bag_solve, ppp_bag_report): opening
// with errors that name the file and say what to do, and reading message by
// message so that one damaged message is skipped and named, not the whole bag
// refused.
//
// Opening refuses, naming the file: a folder ("is a directory"), a file that is
// no bag ("not a bag file": it does not begin with "#ROSBAG V2.0"), and a bag
// rosbag cannot open: without an index (a recording that was stopped) or
// truncated, with the hint to run `rosbag reindex` on it.
// A message whose payload does not deserialize (a damaged record: rosbag's
// "Buffer Overrun") is skipped; its place is named (file, topic, its index on
// the topic, its bag time) with the reason, and the rest of the bag is read.
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <ros/time.h>

namespace rosbag {
class Bag;
class MessageInstance;
}  // namespace rosbag

namespace ppp_ros {

/// A bag that cannot be opened or read; the text names the file.
class BagReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Opens `path` for reading into `bag`. Throws BagReadError naming the file and the reason.
void openBagForReading(rosbag::Bag& bag, const std::string& path);

/// The topic without a leading slash (bags record "gnss/observations" or "/gnss/observations").
std::string relativeBagTopic(const std::string& topic);

/// "BAG: TOPIC message I (bag time 2021-07-29T00:00:00.000 UTC)": where a message is.
std::string bagMessagePlace(const std::string& path, const std::string& topic, std::size_t index,
                            const ros::Time& bag_time);

/// Every message of the open bag in bag time order (rosbag::View), handed to
/// `take` with its index on its topic (0, 1, ... per relative topic). A message
/// `take` throws for (its payload does not deserialize: ros::serialization's
/// "Buffer Overrun", a damaged record) is skipped: "PLACE: cannot be read: REASON"
/// is added to `skipped` and reading goes on. Returns the number of messages.
std::size_t readBagMessages(const rosbag::Bag& bag, const std::string& path,
                            const std::function<void(const rosbag::MessageInstance&, std::size_t)>& take,
                            std::vector<std::string>& skipped);

}  // namespace ppp_ros
