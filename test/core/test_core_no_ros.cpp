// The core library (src/core and include/ppp_bayes_tree outside ros/) must build
// without ROS: this test fails when any of its files includes a ROS, tf2, rosbag
// or message header.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Headers that belong to ROS 1 or its message packages, or to our own ROS adapters.
const std::regex kRosInclude(
    R"(^\s*#\s*include\s*[<"]\s*()"
    R"(ros/|roscpp/|rosbag/|tf2|tf2_ros/|tf2_eigen/|message_filters/|diagnostic_updater/|)"
    R"(actionlib|pluginlib/|nodelet/|image_transport/|)"
    R"([A-Za-z0-9_]+_msgs/|)"
    R"(ppp_bayes_tree/ros/|ppp_bayes_tree/[A-Z][A-Za-z0-9]*\.h))");

std::vector<std::string> rosIncludes(const fs::path& file) {
  std::vector<std::string> hits;
  std::ifstream in(file);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (std::regex_search(line, kRosInclude)) hits.push_back(file.string() + ":" + std::to_string(n) + ": " + line);
  }
  return hits;
}

std::vector<fs::path> coreFiles(const fs::path& repo) {
  std::vector<fs::path> files;
  for (const fs::path root : {repo / "src" / "core", repo / "include" / "ppp_bayes_tree"}) {
    if (!fs::exists(root)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
      if (!entry.is_regular_file()) continue;
      const fs::path& p = entry.path();
      // include/ppp_bayes_tree/ros/ holds the ROS adapters' headers: not core.
      if (p.string().find("/include/ppp_bayes_tree/ros/") != std::string::npos) continue;
      const auto ext = p.extension().string();
      if (ext == ".h" || ext == ".hpp" || ext == ".cpp" || ext == ".cc") files.push_back(p);
    }
  }
  return files;
}

}  // namespace

TEST(CoreNoRos, DetectorRecognisesRosHeaders) {
  // The scanner itself must catch each kind of forbidden include and accept core ones.
  const fs::path tmp = fs::temp_directory_path() / "ppp_core_no_ros_probe.cpp";
  {
    std::ofstream out(tmp);
    out << "#include <ros/ros.h>\n#include <tf2_ros/transform_broadcaster.h>\n"
        << "#include <rosbag/bag.h>\n#include <sensor_msgs/NavSatFix.h>\n"
        << "#include \"ppp_bayes_tree/GnssObservation.h\"\n  #  include <tf2/LinearMath/Quaternion.h>\n"
        << "#include <Eigen/Core>\n#include \"ppp_bayes_tree/types/gnss_time.h\"\n#include <vector>\n";
  }
  EXPECT_EQ(rosIncludes(tmp).size(), 6u);
  fs::remove(tmp);
}

TEST(CoreNoRos, CoreSourcesIncludeNoRosHeader) {
  const fs::path repo = PPP_REPO_DIR;
  const auto files = coreFiles(repo);
  ASSERT_GT(files.size(), 10u) << "core sources not found under " << repo;
  std::vector<std::string> hits;
  for (const auto& f : files) {
    auto h = rosIncludes(f);
    hits.insert(hits.end(), h.begin(), h.end());
  }
  std::string all;
  for (const auto& h : hits) all += "\n  " + h;
  EXPECT_TRUE(hits.empty()) << "core files include ROS headers:" << all;
}
