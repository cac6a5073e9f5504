// The core library (src/core and include/ppp_bayes_tree outside ros/) must build
// without ROS: this test fails when any of its files includes a ROS, tf2, rosbag
// or message header.
//
// Layering: the dependencies of the core point one way. Each folder (the same
// name under include/ppp_bayes_tree and src/core) includes only the folders
// below it (README, "Layout"):
//   types                         time, satellites, codes, frames, record data types
//   io          -> types          readers and writers of the file formats
//   models      -> io             pure models and the product providers
//   smoother    -> types          the generic incremental smoother (no GNSS)
//   ppp         -> models, smoother   measurement model, estimators, pipeline
//   simulation  -> ppp            the flight simulator
//   evaluation  -> simulation     statistics, solution writers, Monte Carlo
//   app         -> evaluation     ppp_solve's run, inspection, replay report
// ("->" includes everything below the named folders; tools and ros sit above app.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
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

namespace {

// The folders each core folder may include (besides itself), transitively closed.
const std::map<std::string, std::set<std::string>>& allowedIncludes() {
  static const std::map<std::string, std::set<std::string>> allowed = [] {
    const std::map<std::string, std::set<std::string>> direct{
        {"types", {}},
        {"io", {"types"}},
        {"models", {"io"}},
        {"smoother", {"types"}},
        {"ppp", {"models", "smoother"}},
        {"simulation", {"ppp"}},
        {"evaluation", {"simulation"}},
        {"app", {"evaluation"}},
    };
    std::map<std::string, std::set<std::string>> closed;
    for (const auto& [folder, below] : direct) {
      std::vector<std::string> todo(below.begin(), below.end());
      while (!todo.empty()) {
        const std::string f = todo.back();
        todo.pop_back();
        if (!closed[folder].insert(f).second) continue;
        for (const auto& g : direct.at(f)) todo.push_back(g);
      }
      closed[folder];
    }
    return closed;
  }();
  return allowed;
}

const std::regex kProjectInclude(R"(^\s*#\s*include\s*"ppp_bayes_tree/([a-z_]+)/)");

/// "file:line: folder includes X" for every include outside the allowed folders.
std::vector<std::string> layeringViolations(const fs::path& file, const std::string& folder) {
  std::vector<std::string> out;
  const auto& allowed = allowedIncludes();
  const auto it = allowed.find(folder);
  std::ifstream in(file);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    std::smatch m;
    if (!std::regex_search(line, m, kProjectInclude)) continue;
    const std::string target = m[1];
    if (target == folder) continue;
    if (it == allowed.end() || !it->second.count(target))
      out.push_back(file.string() + ":" + std::to_string(n) + ": " + folder + " includes " + target);
  }
  return out;
}

}  // namespace

TEST(CoreLayering, DetectorRecognisesUpwardIncludes) {
  const fs::path tmp = fs::temp_directory_path() / "ppp_core_layering_probe.h";
  {
    std::ofstream out(tmp);
    out << "#include \"ppp_bayes_tree/types/gnss_time.h\"\n#include \"ppp_bayes_tree/io/products/sp3_reader.h\"\n"
        << "#include \"ppp_bayes_tree/models/precise_ephemeris.h\"\n#include \"ppp_bayes_tree/ppp/estimators/ekf_ppp.h\"\n"
        << "  #  include \"ppp_bayes_tree/evaluation/monte_carlo.h\"\n";
  }
  EXPECT_EQ(layeringViolations(tmp, "io").size(), 3u);      // models, ppp, evaluation
  EXPECT_EQ(layeringViolations(tmp, "ppp").size(), 1u);     // evaluation
  EXPECT_EQ(layeringViolations(tmp, "app").size(), 0u);
  EXPECT_EQ(layeringViolations(tmp, "smoother").size(), 4u);  // all but types
  EXPECT_EQ(layeringViolations(tmp, "unknown").size(), 5u);   // a new folder must be placed in the table
  fs::remove(tmp);
}

TEST(CoreLayering, EachFolderIncludesOnlyTheFoldersBelowIt) {
  const fs::path repo = PPP_REPO_DIR;
  std::vector<std::string> hits;
  std::set<std::string> folders;
  for (const fs::path root : {repo / "src" / "core", repo / "include" / "ppp_bayes_tree"}) {
    if (!fs::exists(root)) continue;
    for (const auto& dir : fs::directory_iterator(root)) {
      if (!dir.is_directory()) continue;
      const std::string folder = dir.path().filename().string();
      if (folder == "ros") continue;  // the ROS adapters sit above the core
      folders.insert(folder);
      for (const auto& entry : fs::recursive_directory_iterator(dir.path())) {
        if (!entry.is_regular_file()) continue;
        auto v = layeringViolations(entry.path(), folder);
        hits.insert(hits.end(), v.begin(), v.end());
      }
    }
  }
  EXPECT_GE(folders.size(), 8u);
  std::string all;
  for (const auto& h : hits) all += "\n  " + h;
  EXPECT_TRUE(hits.empty()) << "includes against the layering:" << all;
}
