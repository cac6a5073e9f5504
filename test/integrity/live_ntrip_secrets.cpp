// rostest (live_ntrip_secrets.test): an NTRIP password must appear in none of the
// parameter server, /rosout, the nodes' log files (their stdout/stderr and the ROS log
// directory of the run), /diagnostics, PppStatus (ekf/ and smoother/ppp/status), a bag
// recorded of every topic, and the stderr of a failed start.
//   clean:  ppp_stream_node "receiver_stream" with the password in its spec connects
//           (the spec in rosparam is masked at start), a second node takes the password
//           from a credentials file (mode 0600) and connects too;
//   faulty: mistyped specs carrying the password (NTRIP://, a leading space, ntrip:/, an
//           unescaped '?') and a group-readable credentials file: each node refuses to
//           start, and its stderr names the problem without the password.
// Two minutes of week-rollover-STR24.rtcm3 go through the caster so that both PPP nodes
// publish statuses and diagnostics while the recorder runs.
#include <topic_tools/shape_shifter.h>

#include <sys/stat.h>

#include "loopback_servers.h"
#include "rostest/live_support.h"

namespace {

const std::string kPassword = "Pw4Test-Zq9";

/// Every message of some topics, serialized, to search for the password.
struct RawMessages {
  std::mutex mutex;
  std::map<std::string, std::string> bytes;  // topic -> all its messages' bytes
  std::map<std::string, std::size_t> count;
  std::vector<ros::Subscriber> subs;
  void subscribe(ros::NodeHandle& nh, const std::string& topic) {
    subs.push_back(nh.subscribe<topic_tools::ShapeShifter>(topic, 10000, [this, topic](const auto& m) {
      std::vector<std::uint8_t> buffer(m->size());
      ros::serialization::OStream out(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
      m->write(out);
      std::lock_guard<std::mutex> l(mutex);
      bytes[topic].append(buffer.begin(), buffer.end());
      ++count[topic];
    }));
  }
};

bool holdsPassword(const std::string& text) { return text.find(kPassword) != std::string::npos; }

/// Waits for the exit of a child that should fail to start; its log (stdout + stderr).
std::string failedStart(const std::string& name, const std::vector<std::string>& env_free_args,
                        const std::filesystem::path& dir) {
  const std::string log = (dir / (name + ".log")).string();
  ppp_ros::test::ChildProcess child(env_free_args, log);
  for (int i = 0; i < 100 && child.running(); ++i) ros::WallDuration(0.1).sleep();
  EXPECT_FALSE(child.running()) << name << " started with a bad spec";
  return ppp::test::readFileBytes(log);
}

std::string allFilesUnder(const std::filesystem::path& dir, std::size_t* files) {
  std::string text;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    text += ppp::test::readFileBytes(it->path().string());
    ++*files;
  }
  return text;
}

TEST(LiveNtripSecrets, PasswordAppearsNowhere) {
  PPP_REQUIRE_SHARED_DATA();
  if (!ppp::test::str2strAvailable()) GTEST_SKIP() << "RTKLIB str2str is not installed (Debian package rtklib)";
  using namespace ppp_ros::test;
  const auto dir = ppp::test::tempDir("live_ntrip_secrets");
  ros::NodeHandle nh;
  RawMessages raw;
  for (const char* topic : {"/rosout", "/diagnostics", "/ekf/ppp/status", "/smoother/ppp/status"})
    raw.subscribe(nh, topic);
  const std::string bag = (dir / "all.bag").string();
  ChildProcess recorder({"rosbag", "record", "-a", "-O", bag, "__name:=secrets_recorder"},
                        (dir / "recorder.log").string());

  const int port = ppp::test::freeLoopbackPort();
  ppp::test::Str2str caster("ntripc://rover:" + kPassword + "@:" + std::to_string(port) + "/STR24");
  ASSERT_TRUE(caster.running());
  const std::string where = "127.0.0.1:" + std::to_string(port) + "/STR24";
  const std::string node = std::string(PPP_BIN_DIR) + "/ppp_stream_node";

  // Faulty: mistyped specs and a credentials file others may read; each start fails.
  const auto group_readable = dir / "credentials_0644";
  std::ofstream(group_readable) << "rover:" << kPassword << "\n";
  ::chmod(group_readable.c_str(), 0644);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"upper_scheme", "NTRIP://rover:" + kPassword + "@" + where},
      {"leading_space", " ntrip://rover:" + kPassword + "@" + where},
      {"one_slash", "ntrip:/rover:" + kPassword + "@" + where},
      {"unescaped_question_mark", "ntrip://rover:Pw4?Test-Zq9@" + where},
      {"group_readable_file", "ntrip://" + where + "?credentials=" + group_readable.string()},
  };
  for (const auto& [name, spec] : bad) {
    const std::string err = failedStart(name, {node, "__name:=bad_" + name, "_input:=" + spec}, dir);
    EXPECT_NE(err.find("cannot start"), std::string::npos) << name << ": " << err;
    EXPECT_FALSE(holdsPassword(err) || err.find("Test-Zq9") != std::string::npos) << name << ": " << err;
  }

  // Clean: the password in the spec (masked in rosparam at start), and from a 0600 file.
  StreamNodeDiagnostics stream;
  std::unique_ptr<ChildProcess> receiver;
  ASSERT_NO_FATAL_FAILURE(startConnectedStreamNode(
      nh, "ntrip://rover:" + kPassword + "@" + where + "?version=2&reconnect_min_s=0.2&reconnect_max_s=1",
      (dir / "receiver_stream.log").string(), stream, &receiver));
  const auto owner_only = dir / "credentials_0600";
  std::ofstream(owner_only) << "# caster account\nrover:" << kPassword << "\n";
  ::chmod(owner_only.c_str(), 0600);
  StreamNodeDiagnostics from_file;
  from_file.subscribe(nh, "file_stream");
  ChildProcess file_node({node, "__name:=file_stream", "_input:=ntrip://" + where + "?credentials=" + owner_only.string(),
                          "_output_topic:=/gnss/from_file", "_diagnostic_period:=0.2"},
                         (dir / "file_stream.log").string());
  EXPECT_TRUE(from_file.waitFor("connects", "1", 20.0)) << from_file.value("last error");

  // Two minutes of data, so that statuses and diagnostics flow while the recorder runs.
  const std::string recording = ppp::test::readFileBytes(str24Recording());
  const std::size_t part = std::min<std::size_t>(recording.size(), 120 * 1024);
  for (std::size_t done = 0; done < part; done += 2048) ASSERT_TRUE(caster.write(recording.substr(done, 2048)));
  EXPECT_TRUE(waitForSubscriberCount("/gnss/receiver", 2, 5.0));
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::WallTime::now() < until) {
    {
      std::lock_guard<std::mutex> l(raw.mutex);
      if (raw.count["/ekf/ppp/status"] > 20 && raw.count["/smoother/ppp/status"] > 20) break;
    }
    ros::WallDuration(0.2).sleep();
  }
  ros::WallDuration(2.0).sleep();

  // rosparam: the whole parameter server.
  XmlRpc::XmlRpcValue all;
  ASSERT_TRUE(nh.getParam("/", all));
  EXPECT_FALSE(holdsPassword(all.toXml())) << "the password is in the parameter server";
  std::string input;
  ASSERT_TRUE(nh.getParam("/receiver_stream/input", input));
  EXPECT_NE(input.find("rover:***@"), std::string::npos) << input;

  // Topics: /rosout, /diagnostics, PppStatus.
  {
    std::lock_guard<std::mutex> l(raw.mutex);
    EXPECT_GT(raw.count["/ekf/ppp/status"], 0u) << "no PppStatus from the EKF node";
    EXPECT_GT(raw.count["/smoother/ppp/status"], 0u) << "no PppStatus from the smoother node";
    EXPECT_GT(raw.count["/diagnostics"], 0u);
    EXPECT_GT(raw.count["/rosout"], 0u);
    for (const auto& [topic, bytes] : raw.bytes) EXPECT_FALSE(holdsPassword(bytes)) << "the password is on " << topic;
  }

  // The recorded bag (every topic).
  recorder.stop();
  std::string bag_bytes = ppp::test::readFileBytes(bag);
  if (bag_bytes.empty()) bag_bytes = ppp::test::readFileBytes(bag + ".active");
  EXPECT_GT(bag_bytes.size(), 10000u) << "the recorder wrote no bag";
  EXPECT_FALSE(holdsPassword(bag_bytes)) << "the password is in the recorded bag";

  // The nodes' log files: their stdout/stderr here, and the ROS log directory of the run.
  receiver.reset();
  file_node.stop();
  for (const char* log : {"receiver_stream.log", "file_stream.log"})
    EXPECT_FALSE(holdsPassword(ppp::test::readFileBytes((dir / log).string()))) << log;
  std::string run_id;
  nh.getParam("/run_id", run_id);
  const char* log_dir = std::getenv("ROS_LOG_DIR");
  const char* ros_home = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  const std::filesystem::path logs = log_dir ? std::filesystem::path(log_dir)
                                     : ros_home ? std::filesystem::path(ros_home) / "log"
                                                : std::filesystem::path(home ? home : "/tmp") / ".ros" / "log";
  std::size_t ros_files = 0;
  std::string ros_logs = allFilesUnder(logs / run_id, &ros_files);
  // The roslaunch / rostest log of this run sits beside the run's directory.
  std::error_code ec;
  const auto recent = std::filesystem::file_time_type::clock::now() - std::chrono::minutes(5);
  for (const auto& entry : std::filesystem::directory_iterator(logs, ec)) {
    if (!entry.is_regular_file() || entry.last_write_time() < recent) continue;
    ros_logs += ppp::test::readFileBytes(entry.path().string());
    ++ros_files;
  }
  EXPECT_GT(ros_files, 0u) << "no log file of the run found under " << logs;
  std::printf("[ figures  ] %zu log files of the run under %s searched, %zu bytes of bag\n", ros_files,
              logs.c_str(), bag_bytes.size());
  EXPECT_FALSE(holdsPassword(ros_logs)) << "the password is in a file under " << (logs / run_id);
}

// Absurd node parameters refuse the start with the key and the range (stderr); the same
// node with a sane value runs. ppp_stream_node: ~diagnostic_period 0 (was: /diagnostics at
// the loop's rate, ~90 Hz), ~input file:// of a directory (was: "the replayed file ended");
// ppp_smoother_node: smoother/fixed_lag_s 1e9, estimator/min_satellites 1000.
TEST(LiveNodeParameters, AbsurdValuesRefuseTheStartSaneOnesRun) {
  using namespace ppp_ros::test;
  const auto dir = ppp::test::tempDir("live_node_parameters");
  const auto recording = dir / "empty.rtcm3";
  std::ofstream(recording) << "";
  const std::string stream_node = std::string(PPP_BIN_DIR) + "/ppp_stream_node";
  const std::string smoother_node = std::string(PPP_BIN_DIR) + "/ppp_smoother_node";
  struct Case {
    std::string name;
    std::vector<std::string> argv;
    std::string expected;  // in stderr
  };
  const std::vector<Case> faulty = {
      {"diagnostic_period_0",
       {stream_node, "__name:=period0", "_input:=file://" + recording.string(), "_diagnostic_period:=0.0"},
       "~diagnostic_period must be in [0.1, 3600] s"},
      {"file_of_directory", {stream_node, "__name:=filedir", "_input:=file://" + dir.string()}, "is a directory"},
      {"fixed_lag_1e9", {smoother_node, "__name:=lag1e9", "_smoother/fixed_lag_s:=1.0e+9"},
       "smoother.fixed_lag_s: must be in [0, 3600]"},
      {"min_satellites_1000", {smoother_node, "__name:=minsat1000", "_estimator/min_satellites:=1000"},
       "estimator.min_satellites: must be in [1, 100]"},
  };
  for (const Case& c : faulty) {
    const std::string err = failedStart(c.name, c.argv, dir);
    EXPECT_NE(err.find(c.expected), std::string::npos) << c.name << ": " << err;
  }
  // Clean: a period of 1 s and a real file: the node runs (still up after 3 s).
  ChildProcess sane({stream_node, "__name:=period1", "_input:=file://" + recording.string(), "_diagnostic_period:=1.0"},
                    (dir / "sane.log").string());
  ros::WallDuration(3.0).sleep();
  EXPECT_TRUE(sane.running()) << ppp::test::readFileBytes((dir / "sane.log").string());
}

}  // namespace

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "integrity_live_ntrip_secrets"); }
