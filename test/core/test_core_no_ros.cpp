// The core library (src/core and include/ppp_bayes_tree outside ros/) must build
// without ROS: this test fails when any of its files includes a ROS, tf2, rosbag
// or message header.
//
// Layering: the dependencies of the core point one way. Each folder (the same
// name under include/ppp_bayes_tree and src/core) includes only the folders
// below it (README, "Layout"):
//   types                         time, satellites, codes, frames, record data types
//   io          -> types          readers and writers of the file formats (io/ itself: what
//                                 every part shares: parse errors, fixed-width fields, line
//                                 and bit readers, stream problems, the epoch-time screen)
//   models      -> io             pure models and the product providers
//   smoother    -> types          the generic incremental smoother (no GNSS)
//   navigation  -> smoother       IMU readings, SO(3), preintegration, the IMU factor's error,
//                                 the strapdown INS, its error model, coarse alignment, the
//                                 NavState as a smoother variable and the smoother's IMU factors
//   ppp         -> models, smoother, navigation   measurement model, estimators, pipeline
//   simulation  -> ppp, io/imu    the flight simulator (its IMU readings use navigation)
//   evaluation  -> simulation     statistics, solution writers, Monte Carlo
//   app         -> evaluation     ppp_solve's run, inspection, replay report, the live input
// ("->" includes everything below the named folders; tools and ros sit above app.)
//
// Inside io/ and ppp/ the named parts have a direction of their own:
//   io/rinex      -> io                RINEX observation and navigation files, Hatanaka,
//                                      the observation sources
//   io/products   -> io                SP3, RINEX clock, ANTEX, Bias-SINEX, BLQ
//   io/rtcm       -> io/rinex          RTCM 3 framing, MSM, ephemerides, SSR
//   io/ubx        -> io/rinex          u-blox UBX (rtcm and ubx side by side: the stream
//                                      epoch both give is io/stream_epoch.h)
//   io/transport  -> io/rtcm, io/ubx   byte sources (file replay, NTRIP, TCP, serial),
//                                      stream formats and the stream decoder of both
//   io/imu        -> io, navigation    IMU text files (logged IMU with time tags, plain CSV)
//   ppp/model     -> models, smoother  signals, arcs, measurement model, state layout
//   ppp/screening -> ppp/model         prefit and postfit screening
//   ppp/ambiguity -> ppp/model         wide lane, LAMBDA, PPP-AR, product consistency
//   ppp/estimators -> ppp/screening, ppp/ambiguity, navigation   EKF, GNSS/INS EKF, smoother,
//                                      the estimator interface
//   ppp/config    -> ppp/estimators    PppConfig and its YAML binding
//   ppp/pipeline  -> ppp/config        epoch processor, products, pipeline
// A folder above io or ppp may include all of its parts (models: io/transport and
// io/products; simulation: ppp/pipeline and io/imu); a file directly in ppp/ has no part.
//
// The estimation parts of ppp (model, screening, ambiguity, estimators) open no
// file: what they need of the products' files (e.g. the satellite antenna model
// the SP3 and clock headers name) the product assembly reads and hands them as
// data. Their files include neither <fstream> nor io/line_source.h and call no
// stream (fopen, ifstream, ofstream, fstream, open...Source) and no reader
// (read..., summarize...File, productAntennaModel).
//
// The ROS node's parts (src/ros, include/ppp_bayes_tree/ros) go one way too: inputs ->
// outputs -> diagnostics (each counts what it meets; the diagnostics read all).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
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

/// A probe file of the given lines in the temporary folder (removed by the caller).
fs::path writeProbe(const std::string& name, const std::vector<std::string>& lines) {
  const fs::path path = fs::temp_directory_path() / name;
  std::ofstream out(path);
  for (const auto& line : lines) out << line << "\n";
  return path;
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
        {"io/rinex", {"io"}},
        {"io/products", {"io"}},
        {"io/rtcm", {"io/rinex"}},
        {"io/ubx", {"io/rinex"}},
        {"io/transport", {"io/rtcm", "io/ubx"}},
        {"models", {"io/transport", "io/products"}},
        {"smoother", {"types"}},
        {"navigation", {"smoother"}},
        {"io/imu", {"io", "navigation"}},
        {"ppp/model", {"models", "smoother"}},
        {"ppp/screening", {"ppp/model"}},
        {"ppp/ambiguity", {"ppp/model"}},
        {"ppp/estimators", {"ppp/screening", "ppp/ambiguity", "navigation"}},
        {"ppp/config", {"ppp/estimators"}},
        {"ppp/pipeline", {"ppp/config"}},
        {"simulation", {"ppp/pipeline", "io/imu"}},
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

const std::regex kProjectInclude(R"(^\s*#\s*include\s*"ppp_bayes_tree/([a-z_]+)/(?:([a-z_]+)/)?)");

/// The folders with named parts: their sub-folders are layers of their own.
bool hasParts(const std::string& folder) { return folder == "io" || folder == "ppp"; }

/// The layer of a file from its path below include/ppp_bayes_tree or src/core:
/// "ppp/model" for ppp/model/x.h, "io" for io/x.h, "types" for types/x.h.
std::string layerOf(const fs::path& relative) {
  auto it = relative.begin();
  const std::string top = it->string();
  if (!hasParts(top) || std::distance(relative.begin(), relative.end()) < 3) return top;
  return top + "/" + (++it)->string();
}

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
    const std::string top = m[1];
    const std::string target = hasParts(top) && m[2].matched ? top + "/" + m[2].str() : top;
    if (target == folder) continue;
    if (it == allowed.end() || !it->second.count(target))
      out.push_back(file.string() + ":" + std::to_string(n) + ": " + folder + " includes " + target);
  }
  return out;
}

/// Every file of the core outside ros/ with its layer (layerOf).
std::vector<std::pair<fs::path, std::string>> layeredCoreFiles(const fs::path& repo) {
  std::vector<std::pair<fs::path, std::string>> files;
  for (const fs::path root : {repo / "src" / "core", repo / "include" / "ppp_bayes_tree"}) {
    if (!fs::exists(root)) continue;
    for (const auto& dir : fs::directory_iterator(root)) {
      if (!dir.is_directory()) continue;
      if (dir.path().filename() == "ros") continue;  // the ROS adapters sit above the core
      for (const auto& entry : fs::recursive_directory_iterator(dir.path())) {
        if (entry.is_regular_file()) files.emplace_back(entry.path(), layerOf(fs::relative(entry.path(), root)));
      }
    }
  }
  return files;
}

/// The layers that open no file (see the top of this file).
bool opensNoFile(const std::string& layer) {
  return layer == "ppp/model" || layer == "ppp/screening" || layer == "ppp/ambiguity" || layer == "ppp/estimators";
}

const std::regex kFileOpeningInclude(R"(^\s*#\s*include\s*(<fstream>|"ppp_bayes_tree/io/line_source\.h"))");
const std::regex kFileOpeningCall(
    R"(\b(fopen|ifstream|ofstream|fstream|open[A-Za-z]*Source|read[A-Z]\w*|summarize\w*File|productAntennaModel)\b)");

/// "file:line: layer opens files (what)" for every include or call that reads a file, in
/// a layer that opens none; comments are not read.
std::vector<std::string> fileOpeningViolations(const fs::path& file, const std::string& layer) {
  std::vector<std::string> out;
  if (!opensNoFile(layer)) return out;
  std::ifstream in(file);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string code = line.substr(0, line.find("//"));
    std::smatch m;
    if (std::regex_search(code, m, kFileOpeningInclude) || std::regex_search(code, m, kFileOpeningCall))
      out.push_back(file.string() + ":" + std::to_string(n) + ": " + layer + " opens files (" + m[1].str() + ")");
  }
  return out;
}

}  // namespace

TEST(CoreLayering, DetectorRecognisesUpwardIncludes) {
  const fs::path tmp = writeProbe("ppp_core_layering_probe.h",
                                  {"#include \"ppp_bayes_tree/types/gnss_time.h\"",
                                   "#include \"ppp_bayes_tree/io/products/sp3_reader.h\"",
                                   "#include \"ppp_bayes_tree/models/precise_ephemeris.h\"",
                                   "#include \"ppp_bayes_tree/ppp/estimators/ppp_ekf.h\"",
                                   "  #  include \"ppp_bayes_tree/evaluation/monte_carlo.h\""});
  EXPECT_EQ(layeringViolations(tmp, "io/products").size(), 3u);  // models, ppp, evaluation
  EXPECT_EQ(layeringViolations(tmp, "io").size(), 4u);           // and io/products: the base of io is below its parts
  EXPECT_EQ(layeringViolations(tmp, "ppp/pipeline").size(), 1u);  // evaluation
  EXPECT_EQ(layeringViolations(tmp, "app").size(), 0u);
  EXPECT_EQ(layeringViolations(tmp, "smoother").size(), 4u);  // all but types
  EXPECT_EQ(layeringViolations(tmp, "unknown").size(), 5u);   // a new folder must be placed in the table
  EXPECT_EQ(layeringViolations(tmp, "ppp").size(), 5u);       // a file directly in ppp/ belongs to no part
  fs::remove(tmp);
}

TEST(CoreLayering, DetectorKnowsTheDirectionInsidePppAndIo) {
  const fs::path tmp = writeProbe("ppp_core_layering_parts_probe.h",
                                  {"#include \"ppp_bayes_tree/ppp/model/arc_tracker.h\"",
                                   "#include \"ppp_bayes_tree/ppp/screening/prefit_screening.h\"",
                                   "#include \"ppp_bayes_tree/ppp/ambiguity/ambiguity_resolution.h\"",
                                   "#include \"ppp_bayes_tree/ppp/estimators/ppp_ekf.h\"",
                                   "#include \"ppp_bayes_tree/ppp/config/ppp_config.h\"",
                                   "#include \"ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h\"",
                                   "#include \"ppp_bayes_tree/io/parse_error.h\"",
                                   "#include \"ppp_bayes_tree/io/rinex/rinex_obs_reader.h\"",
                                   "#include \"ppp_bayes_tree/io/products/sp3_reader.h\"",
                                   "#include \"ppp_bayes_tree/io/rtcm/rtcm3_decoder.h\"",
                                   "#include \"ppp_bayes_tree/io/ubx/ubx_decoder.h\"",
                                   "#include \"ppp_bayes_tree/io/transport/byte_source.h\""});
  // An estimator including the configuration (as one of its headers once did) is refused.
  const auto estimators = layeringViolations(tmp, "ppp/estimators");
  ASSERT_EQ(estimators.size(), 2u);  // config, pipeline
  EXPECT_NE(estimators[0].find("ppp/estimators includes ppp/config"), std::string::npos) << estimators[0];
  EXPECT_NE(estimators[1].find("ppp/estimators includes ppp/pipeline"), std::string::npos) << estimators[1];
  EXPECT_EQ(layeringViolations(tmp, "ppp/pipeline").size(), 0u);  // the top of ppp includes all of it and all of io
  EXPECT_EQ(layeringViolations(tmp, "ppp/config").size(), 1u);    // pipeline
  // screening and ambiguity sit side by side on the model: neither includes the other.
  EXPECT_EQ(layeringViolations(tmp, "ppp/screening").size(), 4u);  // ambiguity, estimators, config, pipeline
  EXPECT_EQ(layeringViolations(tmp, "ppp/ambiguity").size(), 4u);  // screening, estimators, config, pipeline
  EXPECT_EQ(layeringViolations(tmp, "ppp/model").size(), 5u);        // every other part of ppp
  // io: the base, then rinex and products side by side, rtcm and ubx side by side on
  // rinex, transport on top.
  EXPECT_EQ(layeringViolations(tmp, "io").size(), 11u);            // everything but itself
  EXPECT_EQ(layeringViolations(tmp, "io/rinex").size(), 10u);      // ppp (6), products, rtcm, ubx, transport
  EXPECT_EQ(layeringViolations(tmp, "io/rtcm").size(), 9u);        // ppp (6), products, ubx, transport
  EXPECT_EQ(layeringViolations(tmp, "io/ubx").size(), 9u);         // ppp (6), products, rtcm, transport
  EXPECT_EQ(layeringViolations(tmp, "io/transport").size(), 7u);   // ppp (6), products
  EXPECT_EQ(layeringViolations(tmp, "models").size(), 6u);         // ppp (6): models see all of io
  fs::remove(tmp);
}

TEST(CoreLayering, EstimatorsSitAboveNavigationNotTheOtherWay) {
  const fs::path tmp = writeProbe("ppp_core_layering_navigation_probe.h",
                                  {"#include \"ppp_bayes_tree/navigation/ins_error_state.h\"",
                                   "#include \"ppp_bayes_tree/ppp/estimators/ppp_ins_ekf.h\"",
                                   "#include \"ppp_bayes_tree/io/imu/imu_csv_reader.h\""});
  // The GNSS/INS estimator includes the navigation layer; the readers of IMU files stay above it.
  const auto estimators = layeringViolations(tmp, "ppp/estimators");
  ASSERT_EQ(estimators.size(), 1u);  // io/imu
  EXPECT_NE(estimators[0].find("ppp/estimators includes io/imu"), std::string::npos) << estimators[0];
  // The navigation layer includes nothing of ppp nor of io.
  const auto navigation = layeringViolations(tmp, "navigation");
  ASSERT_EQ(navigation.size(), 2u);  // ppp/estimators, io/imu
  EXPECT_NE(navigation[0].find("navigation includes ppp/estimators"), std::string::npos) << navigation[0];
  fs::remove(tmp);
}

TEST(CoreLayering, EachFolderIncludesOnlyTheFoldersBelowIt) {
  const fs::path repo = PPP_REPO_DIR;
  const auto& allowed = allowedIncludes();
  std::vector<std::string> hits;
  std::set<std::string> layers;
  for (const auto& [file, layer] : layeredCoreFiles(repo)) {
    layers.insert(layer);
    if (!allowed.count(layer)) hits.push_back(file.string() + ": in no layer of the table (" + layer + ")");
    auto v = layeringViolations(file, layer);
    hits.insert(hits.end(), v.begin(), v.end());
  }
  // Every layer of the table holds files: the six parts of ppp and the five of io.
  for (const auto& [layer, below] : allowed) EXPECT_TRUE(layers.count(layer)) << "no file in " << layer;
  std::string all;
  for (const auto& h : hits) all += "\n  " + h;
  EXPECT_TRUE(hits.empty()) << "includes against the layering:" << all;
}

TEST(CoreLayering, TypesIsTheBase) {
  // The shared data types (the observation epoch among them) include nothing else of the project.
  const fs::path tmp = writeProbe("ppp_core_layering_types_probe.h",
                                  {"#include \"ppp_bayes_tree/types/obs_epoch.h\"",
                                   "#include \"ppp_bayes_tree/io/stream_epoch.h\"",
                                   "#include \"ppp_bayes_tree/io/rinex/rinex_obs_header.h\"",
                                   "#include \"ppp_bayes_tree/smoother/isam2.h\""});
  const auto types = layeringViolations(tmp, "types");
  ASSERT_EQ(types.size(), 3u);  // io, io/rinex, smoother
  EXPECT_NE(types[0].find(":2: types includes io"), std::string::npos) << types[0];
  EXPECT_NE(types[1].find(":3: types includes io/rinex"), std::string::npos) << types[1];
  EXPECT_EQ(layeringViolations(tmp, "smoother").size(), 2u);  // io, io/rinex: the smoother sees only types
  EXPECT_EQ(layeringViolations(tmp, "io").size(), 2u);        // io/rinex, smoother
  fs::remove(tmp);
}

TEST(CoreLayering, RtcmAndUbxAreSiblings) {
  // Neither receiver format includes the other; both see the stream epoch of the io base
  // and the RINEX layout of io/rinex; the transport sees both.
  const fs::path tmp = writeProbe("ppp_core_layering_framers_probe.h",
                                  {"#include \"ppp_bayes_tree/io/stream_epoch.h\"",
                                   "#include \"ppp_bayes_tree/io/rinex/stream_epoch_layout.h\"",
                                   "#include \"ppp_bayes_tree/io/rtcm/rtcm_observation_source.h\"",
                                   "#include \"ppp_bayes_tree/io/ubx/ubx_observation_source.h\""});
  const auto ubx = layeringViolations(tmp, "io/ubx");
  ASSERT_EQ(ubx.size(), 1u);
  EXPECT_NE(ubx[0].find(":3: io/ubx includes io/rtcm"), std::string::npos) << ubx[0];
  const auto rtcm = layeringViolations(tmp, "io/rtcm");
  ASSERT_EQ(rtcm.size(), 1u);
  EXPECT_NE(rtcm[0].find(":4: io/rtcm includes io/ubx"), std::string::npos) << rtcm[0];
  EXPECT_EQ(layeringViolations(tmp, "io/transport").size(), 0u);
  EXPECT_EQ(layeringViolations(tmp, "io/rinex").size(), 2u);  // rtcm, ubx
  fs::remove(tmp);
}

TEST(CoreLayering, DetectorRecognisesFileOpening) {
  // productAntennaModel(path) once opened the SP3 and clock files from ppp/ambiguity.
  const fs::path tmp = writeProbe("ppp_core_file_opening_probe.cpp",
                                  {"#include \"ppp_bayes_tree/io/line_source.h\"",
                                   "#include \"ppp_bayes_tree/io/fixed_width.h\"",
                                   "#include <fstream>",
                                   "#include <cstdio>",
                                   "auto src = openLineSource(path);",
                                   "std::ifstream in(path);",
                                   "std::FILE* f = std::fopen(path.c_str(), \"rb\");",
                                   "const Sp3File sp3 = readSp3(path);",
                                   "models.push_back(productAntennaModel(f));",
                                   "const FileSummary s = summarizeClockFile(path);",
                                   "// a comment may say readSp3(path) or std::ifstream",
                                   "std::snprintf(buf, sizeof buf, \"%d\", n);  // thread, spread(, already(",
                                   "const double spread_m = threadedValue(x);"});
  const auto ambiguity = fileOpeningViolations(tmp, "ppp/ambiguity");
  ASSERT_EQ(ambiguity.size(), 8u);  // lines 1, 3, 5-10
  EXPECT_NE(ambiguity[0].find(":1: ppp/ambiguity opens files (\"ppp_bayes_tree/io/line_source.h\")"), std::string::npos)
      << ambiguity[0];
  EXPECT_NE(ambiguity[7].find(":10: ppp/ambiguity opens files (summarizeClockFile)"), std::string::npos) << ambiguity[7];
  for (const char* layer : {"ppp/model", "ppp/screening", "ppp/estimators"})
    EXPECT_EQ(fileOpeningViolations(tmp, layer).size(), 8u) << layer;
  // The parts that read files: the pipeline (the product assembly), the configuration, io, models.
  for (const char* layer : {"ppp/pipeline", "ppp/config", "io/products", "models", "app"})
    EXPECT_EQ(fileOpeningViolations(tmp, layer).size(), 0u) << layer;
  fs::remove(tmp);
}

TEST(CoreLayering, EstimationPartsOpenNoFile) {
  const fs::path repo = PPP_REPO_DIR;
  std::vector<std::string> hits;
  std::size_t checked = 0;
  for (const auto& [file, layer] : layeredCoreFiles(repo)) {
    if (opensNoFile(layer)) ++checked;
    auto v = fileOpeningViolations(file, layer);
    hits.insert(hits.end(), v.begin(), v.end());
  }
  EXPECT_GT(checked, 20u) << "the files of ppp/model, screening, ambiguity and estimators not found under " << repo;
  std::string all;
  for (const auto& h : hits) all += "\n  " + h;
  EXPECT_TRUE(hits.empty()) << "files opened below the product assembly:" << all;
}

namespace {

/// The node parts each node part may include (node_<part>.h).
const std::map<std::string, std::set<std::string>> kNodeParts{
    {"node_inputs", {}},
    {"node_outputs", {"node_inputs"}},
    {"node_diagnostics", {"node_inputs", "node_outputs"}},
};

const std::regex kNodePartInclude(R"(^\s*#\s*include\s*"ppp_bayes_tree/ros/(node_[a-z]+)\.h")");

/// "file:line: part includes other" for every include of a node part above `part`.
std::vector<std::string> nodePartViolations(const fs::path& file, const std::string& part) {
  std::vector<std::string> out;
  const auto allowed = kNodeParts.find(part);
  if (allowed == kNodeParts.end()) return out;
  std::ifstream in(file);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    std::smatch m;
    if (!std::regex_search(line, m, kNodePartInclude)) continue;
    const std::string target = m[1];
    if (target != part && kNodeParts.count(target) && !allowed->second.count(target))
      out.push_back(file.string() + ":" + std::to_string(n) + ": " + part + " includes " + target);
  }
  return out;
}

}  // namespace

TEST(RosNodeParts, DetectorRecognisesBackwardIncludes) {
  const fs::path tmp = writeProbe("ppp_node_parts_probe.cpp",
                                  {"#include \"ppp_bayes_tree/ros/node_inputs.h\"",
                                   "#include \"ppp_bayes_tree/ros/node_outputs.h\"",
                                   "#include \"ppp_bayes_tree/ros/node_diagnostics.h\"",
                                   "#include \"ppp_bayes_tree/ros/node_options.h\""});
  const auto inputs = nodePartViolations(tmp, "node_inputs");
  ASSERT_EQ(inputs.size(), 2u);  // outputs, diagnostics
  EXPECT_NE(inputs[0].find(":2: node_inputs includes node_outputs"), std::string::npos) << inputs[0];
  EXPECT_EQ(nodePartViolations(tmp, "node_outputs").size(), 1u);  // diagnostics
  EXPECT_EQ(nodePartViolations(tmp, "node_diagnostics").size(), 0u);
  EXPECT_EQ(nodePartViolations(tmp, "ppp_node").size(), 0u);  // the node holds them all
  fs::remove(tmp);
}

TEST(RosNodeParts, InputsOutputsDiagnosticsGoOneWay) {
  const fs::path repo = PPP_REPO_DIR;
  std::vector<std::string> hits;
  std::size_t checked = 0;
  for (const fs::path dir : {repo / "src" / "ros", repo / "include" / "ppp_bayes_tree" / "ros"}) {
    if (!fs::exists(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string part = entry.path().stem().string();
      if (!entry.is_regular_file() || !kNodeParts.count(part)) continue;
      ++checked;
      auto v = nodePartViolations(entry.path(), part);
      hits.insert(hits.end(), v.begin(), v.end());
    }
  }
  EXPECT_EQ(checked, 6u) << "node_inputs, node_outputs, node_diagnostics (.h and .cpp) not found under " << repo;
  std::string all;
  for (const auto& h : hits) all += "\n  " + h;
  EXPECT_TRUE(hits.empty()) << "node parts including a part above them:" << all;
}
