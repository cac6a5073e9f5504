#include "ppp_bayes_tree/ros/bag_reader.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <boost/date_time/posix_time/posix_time.hpp>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>

namespace ppp_ros {
namespace {

namespace fs = std::filesystem;

constexpr char kBagMagic[] = "#ROSBAG V2.0\n";  // the first line of every bag of format 2.0

std::string reindexHint(const std::string& path) {
  return "if it is a recording that was stopped or cut short, `rosbag reindex " + path + "` may recover it";
}

/// The file is there, is a file, and begins as a bag of format 2.0.
void checkBagFile(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw BagReadError(path + ": is a directory, not a bag file");
  if (!fs::exists(path, ec)) throw BagReadError(path + ": no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw BagReadError(path + ": cannot be opened: " + std::strerror(errno));
  char head[sizeof kBagMagic - 1] = {};
  in.read(head, sizeof head);
  const std::string begins(head, static_cast<std::size_t>(in.gcount()));
  if (begins == kBagMagic) return;
  if (begins.rfind("#ROSBAG V", 0) == 0)
    throw BagReadError(path + ": a bag of format " + begins.substr(9, begins.find('\n') - 9) +
                       ", not 2.0 (rosbag migrate, or a recent rosbag record)");
  throw BagReadError(path + ": not a bag file (it does not begin with \"#ROSBAG V2.0\")");
}

std::string isoUtc(const ros::Time& t) {
  try {
    return boost::posix_time::to_iso_extended_string(t.toBoost()) + " UTC";
  } catch (const std::exception&) {  // out of boost's calendar
    return std::to_string(t.toSec()) + " s";
  }
}

}  // namespace

void openBagForReading(rosbag::Bag& bag, const std::string& path) {
  checkBagFile(path);
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    throw BagReadError(path + ": the bag has no index (a recording that was stopped, or a file cut short); "
                              "rebuild it with `rosbag reindex " + path + "`");
  } catch (const rosbag::BagException& e) {
    throw BagReadError(path + ": cannot be read as a bag (rosbag: " + e.what() + "); " + reindexHint(path));
  }
}

std::string relativeBagTopic(const std::string& topic) {
  return topic.rfind('/', 0) == 0 ? topic.substr(1) : topic;
}

std::string bagMessagePlace(const std::string& path, const std::string& topic, std::size_t index,
                            const ros::Time& bag_time) {
  return path + ": " + topic + " message " + std::to_string(index) + " (bag time " + isoUtc(bag_time) + ")";
}

std::size_t readBagMessages(const rosbag::Bag& bag, const std::string& path,
                            const std::function<void(const rosbag::MessageInstance&, std::size_t)>& take,
                            std::vector<std::string>& skipped) {
  std::map<std::string, std::size_t> next_index;  // relative topic -> index of its next message
  std::size_t read = 0;
  try {
    rosbag::View view(bag);
    for (const rosbag::MessageInstance& m : view) {
      const std::string topic = relativeBagTopic(m.getTopic());
      const std::size_t index = next_index[topic]++;
      ++read;
      try {
        take(m, index);
      } catch (const rosbag::BagException& e) {
        skipped.push_back(bagMessagePlace(path, topic, index, m.getTime()) + ": cannot be read: rosbag: " + e.what());
      } catch (const std::exception& e) {  // ros::serialization::StreamOverrunException and the like
        skipped.push_back(bagMessagePlace(path, topic, index, m.getTime()) + ": cannot be read: " + e.what());
      }
    }
  } catch (const rosbag::BagException& e) {
    throw BagReadError(path + ": reading stopped after " + std::to_string(read) + " messages (rosbag: " + e.what() +
                       "); " + reindexHint(path));
  }
  return read;
}

}  // namespace ppp_ros
