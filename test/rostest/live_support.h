#pragma once
// Helpers of the live-input rostests (live_*.cpp): publish a real
// recording as foreign stream messages (exact type name and MD5, through
// topic_tools::ShapeShifter), run the ppp_solve binary on the same recording as
// the reference, and compare a node's fixes with it epoch by epoch; for the
// end-to-end tests through launch/live.launch: both nodes' outputs, a
// ppp_stream_node started by the test (ports picked at run time) and its diagnostics.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Core>
#include <ros/ros.h>
#include <sensor_msgs/NavSatStatus.h>
#include <topic_tools/shape_shifter.h>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ros/ublox_ros_messages.h"
#include "rostest/rostest_support.h"
#include "test_support.h"

namespace ppp_ros::test {

/// One message to publish: on which publisher, what.
struct StreamMessage {
  std::size_t publisher = 0;
  topic_tools::ShapeShifter message;
};

/// `bytes` cut into rtcm_msgs/Message chunks of 1-700 bytes (sizes drawn from a
/// std::mt19937 seeded with `seed`; header.seq 1, 2, ...), for `publisher` 0: an NTRIP
/// client's chunking of a stream, frames split anywhere.
inline std::vector<StreamMessage> rtcmChunkMessages(const std::string& bytes, unsigned seed) {
  const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
  std::vector<StreamMessage> messages;
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::size_t> size(1, 700);
  std::uint32_t seq = 0;
  for (std::size_t cut = 0; cut < bytes.size();) {
    const std::size_t end = std::min(bytes.size(), cut + size(random));
    StreamMessage m;
    m.message = rtcmMessage(std::vector<std::uint8_t>(data + cut, data + end), ++seq);
    messages.push_back(std::move(m));
    cut = end;
  }
  return messages;
}

/// Advertises every (topic, message type) of `messages`' publishers, waits until each has
/// `subscribers` subscribers, then publishes them in order, `spacing_s` apart (wall time:
/// keeps the order across topics at the node, whose callbacks run one after the other).
inline void publishInOrder(ros::NodeHandle& nh, const std::vector<std::string>& topics,
                           std::vector<StreamMessage>& messages, double spacing_s, std::size_t subscribers = 1) {
  std::vector<ros::Publisher> pubs(topics.size());
  for (auto& m : messages)
    if (!pubs[m.publisher]) pubs[m.publisher] = m.message.advertise(nh, topics[m.publisher], 100000);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
  for (auto& p : pubs) {
    while (p && p.getNumSubscribers() < subscribers && ros::WallTime::now() < end) ros::WallDuration(0.05).sleep();
    ASSERT_TRUE(!p || p.getNumSubscribers() >= subscribers) << p.getTopic() << " has no subscriber";
  }
  ros::WallDuration(0.5).sleep();  // connections settle
  for (auto& m : messages) {
    pubs[m.publisher].publish(m.message);
    ros::WallDuration(spacing_s).sleep();
  }
}

/// Reads a solution CSV of ppp_solve (DIR/<name>_ekf.csv, _smoother_filtered.csv): UTC
/// stamp -> ECEF position of the epochs with a solution (`rows`: every epoch row; `fixed`:
/// stamp -> whether the epoch's status is ppp-fixed).
inline std::map<ros::Time, Eigen::Vector3d> readPppSolveCsv(const std::filesystem::path& csv,
                                                            std::size_t* rows = nullptr,
                                                            std::map<ros::Time, bool>* fixed = nullptr) {
  std::map<ros::Time, Eigen::Vector3d> out;
  if (rows) *rows = 0;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) names.push_back(f);
  }
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return i;
    ADD_FAILURE() << "no column " << name << " in " << csv;
    return std::size_t{0};
  };
  const std::size_t week = column("gps_week"), tow = column("tow_s"), x = column("x_m"), y = column("y_m"),
                    z = column("z_m"), status = fixed ? column("status") : 0;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string v; std::getline(ss, v, ',');) f.push_back(v);
    if (rows) ++*rows;
    if (f.size() <= z || f[x].empty()) continue;  // no solution at this epoch
    const ppp::GnssTime t = ppp::GnssTime::fromGpsWeek(std::stoi(f[week]), std::stod(f[tow]));
    out[utcStamp(t)] = Eigen::Vector3d(std::stod(f[x]), std::stod(f[y]), std::stod(f[z]));
    if (fixed) (*fixed)[utcStamp(t)] = f.size() > status && f[status] == "ppp-fixed";
  }
  return out;
}

/// Runs `ppp_solve <args> --estimator <estimator> --name live --out DIR` (exit 0, 3, or 1
/// with a CSV: nothing solved, the caller checks the rows); returns DIR.
inline std::filesystem::path runPppSolve(const std::string& args, const std::string& estimator,
                                         const std::string& tag) {
  const std::filesystem::path dir = ppp::test::tempDir(tag);
  const std::string cmd = std::string(PPP_BIN_DIR) + "/ppp_solve " + args + " --estimator " + estimator +
                          " --name live --out " + dir.string() + " > " + (dir / "ppp_solve.log").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  const int exit_code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  const std::filesystem::path first = dir / (estimator == "smoother" ? "live_smoother_filtered.csv" : "live_ekf.csv");
  EXPECT_TRUE(exit_code == 0 || exit_code == 3 || (exit_code == 1 && std::filesystem::exists(first)))
      << cmd << " exited " << exit_code << ":\n"
      << ppp::test::readFileBytes((dir / "ppp_solve.log").string());
  return dir;
}

/// `ppp_solve <args> --estimator ekf`: UTC stamp -> ECEF position of the epochs with a solution
/// (`rows`: every epoch row, with a solution or not).
inline std::map<ros::Time, Eigen::Vector3d> pppSolveEkf(const std::string& args, const std::string& tag,
                                                        std::size_t* rows = nullptr) {
  return readPppSolveCsv(runPppSolve(args, "ekf", tag) / "live_ekf.csv", rows);
}

/// `ppp_solve <args> --estimator both`: the EKF's and the smoother's FILTERED solutions (the
/// smoother node's ppp/fix is its filtered estimate, the newest state), and their epoch rows.
struct PppSolveBoth {
  std::map<ros::Time, Eigen::Vector3d> ekf, smoother_filtered;
  std::size_t ekf_rows = 0, smoother_rows = 0;
};
inline PppSolveBoth pppSolveBoth(const std::string& args, const std::string& tag) {
  const std::filesystem::path dir = runPppSolve(args, "both", tag);
  PppSolveBoth out;
  out.ekf = readPppSolveCsv(dir / "live_ekf.csv", &out.ekf_rows);
  out.smoother_filtered = readPppSolveCsv(dir / "live_smoother_filtered.csv", &out.smoother_rows);
  return out;
}

/// The node's fixes against ppp_solve's: every fix has a ppp_solve epoch within 1 ms
/// of its stamp, and every ppp_solve epoch (but perhaps the last) a fix; largest 3D difference < 1 mm.
inline void expectEqualToPppSolve(const std::string& what, const std::vector<sensor_msgs::NavSatFix>& fixes,
                                  const std::map<ros::Time, Eigen::Vector3d>& offline) {
  ASSERT_FALSE(offline.empty()) << what << ": ppp_solve solved no epoch";
  double worst = 0.0;
  std::size_t matched = 0;
  for (const auto& f : fixes) {
    auto it = offline.lower_bound(f.header.stamp - ros::Duration(1e-3));
    ASSERT_TRUE(it != offline.end() && std::abs((it->first - f.header.stamp).toSec()) < 1e-3)
        << what << ": no ppp_solve epoch at " << f.header.stamp;
    const double d = (fixEcef(f) - it->second).norm();
    if (std::getenv("PPP_LIVE_DEBUG")) std::printf("%s: %.3f %.6f m\n", what.c_str(), f.header.stamp.toSec(), d);
    worst = std::max(worst, d);
    ++matched;
  }
  std::printf("[ figures  ] %s: %zu node fixes, %zu ppp_solve epochs; largest difference %.3g mm\n", what.c_str(),
              matched, offline.size(), worst * 1e3);
  // Every epoch, but perhaps the last: a live stream does not end, so an epoch whose
  // completeness the decoder cannot tell before the next one arrives may stay held.
  EXPECT_GE(matched + 1, offline.size()) << what;
  EXPECT_LT(worst, 1e-3) << what;
}

/// The ESBC 2020-177 day as one caster stream (the ppp_stream_make binary): the 30 s
/// observations from `start` ("2020/06/25 00:30:00") for `duration_s`, the broadcast file
/// `nav`, the SSR frames of `ssr`; writes dir/ESBC_made.rtcm3 and returns its path.
inline std::string makeEsbcCasterStream(const std::filesystem::path& dir, const std::string& nav,
                                        const std::string& ssr, const std::string& start, int duration_s) {
  const std::string stream = (dir / "ESBC_made.rtcm3").string();
  const std::string make = std::string(PPP_BIN_DIR) + "/ppp_stream_make --obs " +
                           ppp::test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz") +
                           " --nav " + nav + " --ssr " + ssr + " --start '" + start + "' --duration " +
                           std::to_string(duration_s) + " --out " + stream + " > " + (dir / "make.log").string() + " 2>&1";
  EXPECT_EQ(std::system(make.c_str()), 0) << make << "\n" << ppp::test::readFileBytes((dir / "make.log").string());
  return stream;
}

/// The set-up of the ESBC live SSR rostests (live_esbc_ssr, live_esbc_ssr_ar): an SSR
/// stream made by ppp_ssr_encode's code, the caster stream ppp_stream_make makes with it,
/// and that stream as the nodes get it: one rtcm_msgs/Message per frame in the caster's
/// order, SSR on publisher 1 (the correction topic), the rest on 0 (the observation topic).
struct EsbcSsrLiveCase {
  std::string ssr, stream;  // dir/SSRC00TST_esbc.rtcm3, dir/ESBC_made.rtcm3
  std::vector<StreamMessage> messages;
  std::map<int, std::size_t> frames_by_type;
  std::size_t ssr_frames = 0;
  std::size_t framing_problems = 0;
  std::size_t frames(std::initializer_list<int> types) const {
    std::size_t n = 0;
    for (int t : types) n += frames_by_type.count(t) ? frames_by_type.at(t) : 0;
    return n;
  }
  /// ppp_solve's inputs for the case: `--rtcm STREAM --ref-date 2020/06/25 --nav STREAM --ssr SSR
  /// --atx ATX... --config CONFIG...` (configs relative to the repository).
  std::string pppSolveArgs(const std::vector<std::string>& atx, const std::vector<std::string>& configs) const {
    std::string args = "--rtcm " + stream + " --ref-date 2020/06/25 --nav " + stream + " --ssr " + ssr + " --atx";
    for (const auto& a : atx) args += " " + ppp::test::dataPath(a);
    args += " --config";
    for (const auto& c : configs) args += " " + std::string(PPP_REPO_DIR) + "/" + c;
    return args;
  }
};

/// Writes `ssr_bytes` and makes the caster stream from `start` ("2020/06/25 00:30:00") for
/// `duration_s` into `dir` (call through ASSERT_NO_FATAL_FAILURE).
inline void makeEsbcSsrLiveCase(const std::filesystem::path& dir, const std::vector<std::uint8_t>& ssr_bytes,
                                const std::string& start, int duration_s, EsbcSsrLiveCase* out) {
  EsbcSsrLiveCase& c = *out;
  c.ssr = (dir / "SSRC00TST_esbc.rtcm3").string();
  ppp::test::writeFileBytes(c.ssr, ssr_bytes);
  c.stream = makeEsbcCasterStream(dir, ppp::test::dataPath("esbc-2020-177/ESBC00DNK_R_20201770000_01D_MN.rnx"), c.ssr, start,
                                  duration_s);
  ASSERT_FALSE(::testing::Test::HasFailure());
  const std::string bytes = ppp::test::readFileBytes(c.stream);
  std::uint32_t seq = 0;
  ppp::Rtcm3Framer framer;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), [&](const ppp::Rtcm3Frame& f) {
    StreamMessage m;
    const bool correction = ppp::RtcmSsrDecoder::isSsrMessageType(f.message_type);
    m.publisher = correction ? 1 : 0;
    c.ssr_frames += correction ? 1 : 0;
    ++c.frames_by_type[f.message_type];
    const auto* begin = reinterpret_cast<const std::uint8_t*>(bytes.data()) + f.byte_offset;
    m.message = rtcmMessage(std::vector<std::uint8_t>(begin, begin + f.payload.size() + 6), ++seq);
    c.messages.push_back(std::move(m));
  });
  c.framing_problems = framer.counters().totalProblems();
}

/// One row of a ppp_solve solution CSV with a position.
struct SolvedEpoch {
  Eigen::Vector3d position_ecef_m;
  bool fixed = false;
};

/// ppp_solve's CSV: UTC stamp -> position and fix state ("status" ppp-fixed).
inline std::map<ros::Time, SolvedEpoch> readSolutionCsv(const std::filesystem::path& csv) {
  std::map<ros::Time, bool> fixed;
  std::map<ros::Time, SolvedEpoch> out;
  for (const auto& [stamp, p] : readPppSolveCsv(csv, nullptr, &fixed)) out[stamp] = {p, fixed.at(stamp)};
  return out;
}

/// The node's fixes and statuses against ppp_solve: the same epochs, positions within
/// 1 mm, the same fix state in PppStatus and NavSatFix; returns the fixed epochs.
inline std::size_t expectSameFixes(const std::string& what, NodeOutputs& out, const std::map<ros::Time, SolvedEpoch>& offline) {
  std::lock_guard<std::mutex> l(out.mutex);
  std::map<ros::Time, std::uint8_t> fix_state;
  for (const auto& s : out.statuses) fix_state[s.header.stamp] = s.fix_state;
  double worst_m = 0.0;
  std::size_t fixed = 0, state_mismatch = 0;
  for (const auto& f : out.fixes) {
    const auto it = offline.find(f.header.stamp);
    if (it == offline.end()) {
      ADD_FAILURE() << what << ": no ppp_solve epoch at " << f.header.stamp;
      continue;
    }
    worst_m = std::max(worst_m, (fixEcef(f) - it->second.position_ecef_m).norm());
    const bool node_fixed = fix_state[f.header.stamp] == ppp_bayes_tree::PppStatus::FIX_FIXED;
    state_mismatch += node_fixed != it->second.fixed ? 1 : 0;
    EXPECT_EQ(f.status.status, node_fixed ? sensor_msgs::NavSatStatus::STATUS_GBAS_FIX
                                          : sensor_msgs::NavSatStatus::STATUS_FIX) << what << " at " << f.header.stamp;
    fixed += node_fixed ? 1 : 0;
  }
  std::size_t offline_fixed = 0;
  for (const auto& [stamp, e] : offline) offline_fixed += e.fixed ? 1 : 0;
  std::printf("[ figures  ] %s: %zu node fixes (%zu fixed), %zu ppp_solve epochs (%zu fixed); largest difference "
              "%.3g mm; fix state differs at %zu epochs\n",
              what.c_str(), out.fixes.size(), fixed, offline.size(), offline_fixed, worst_m * 1e3, state_mismatch);
  EXPECT_EQ(out.fixes.size(), offline.size()) << what;
  EXPECT_LT(worst_m, 1e-3) << what;
  EXPECT_EQ(state_mismatch, 0u) << what;
  return fixed;
}

/// Waits (wall time) until `out` received `n` fixes and none for `quiet_s`, or the timeout.
inline void waitForFixes(NodeOutputs& out, std::size_t n, double timeout_s, double quiet_s = 3.0) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  std::size_t last = 0;
  ros::WallTime last_change = ros::WallTime::now();
  while (ros::WallTime::now() < end) {
    std::size_t now_n;
    {
      std::lock_guard<std::mutex> l(out.mutex);
      now_n = out.fixes.size();
    }
    if (now_n != last) {
      last = now_n;
      last_change = ros::WallTime::now();
    }
    if (now_n >= n && (ros::WallTime::now() - last_change).toSec() > quiet_s) return;
    ros::WallDuration(0.1).sleep();
  }
}

/// The outputs of launch/live.launch's two nodes: ekf/ppp/* and smoother/ppp/*.
struct LiveLaunchOutputs {
  NodeOutputs ekf, smoother;
  void subscribe(ros::NodeHandle& nh) {
    ekf.subscribe(nh, "/ekf/");
    smoother.subscribe(nh, "/smoother/");
  }
  /// Both nodes' fixes equal ppp_solve's (EKF; smoother filtered) epoch by epoch to 1 mm,
  /// every epoch but perhaps the last; broadcast only, as configured (no correction stream).
  void expectEqualTo(const PppSolveBoth& reference, const std::string& what) {
    std::lock_guard<std::mutex> l1(ekf.mutex), l2(smoother.mutex);
    expectEqualToPppSolve(what + ", ppp_ekf_node vs ppp_solve EKF", ekf.fixes, reference.ekf);
    expectEqualToPppSolve(what + ", ppp_smoother_node vs ppp_solve smoother filtered", smoother.fixes,
                          reference.smoother_filtered);
    for (NodeOutputs* o : {&ekf, &smoother}) {
      ASSERT_FALSE(o->statuses.empty()) << what;
      const auto& last = o->statuses.back();
      std::printf("[ figures  ] %s, %s: %zu statuses received, last: %lu epochs processed, %lu duplicate, %lu out of "
                  "order, %lu resets\n",
                  what.c_str(), last.estimator.c_str(), o->statuses.size(),
                  static_cast<unsigned long>(last.epochs_processed), static_cast<unsigned long>(last.epochs_duplicate),
                  static_cast<unsigned long>(last.epochs_out_of_order),
                  static_cast<unsigned long>(last.estimator_resets));
      EXPECT_EQ(o->statuses.back().product_mode, ppp_bayes_tree::PppStatus::PRODUCTS_BROADCAST_ONLY) << what;
      EXPECT_EQ(o->statuses.back().observations_lost, 0u) << what;
    }
    EXPECT_EQ(ekf.statuses.back().estimator, "ekf");
    EXPECT_EQ(smoother.statuses.back().estimator, "smoother");
  }
};

/// Waits (wall time) until the master lists `n` subscribers of `topic`.
inline bool waitForSubscriberCount(const std::string& topic, std::size_t n, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::WallTime::now() < end) {
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = ros::this_node::getName();
    if (ros::master::execute("getSystemState", args, result, payload, false) && payload.size() >= 2) {
      XmlRpc::XmlRpcValue& subscribers = payload[1];
      for (int i = 0; i < subscribers.size(); ++i)
        if (static_cast<std::string>(subscribers[i][0]) == topic &&
            static_cast<std::size_t>(subscribers[i][1].size()) >= n)
          return true;
    }
    ros::WallDuration(0.1).sleep();
  }
  return false;
}

/// The key/value pairs of the /diagnostics task "stream" of one ppp_stream_node (status
/// name "<node name>: stream"), the latest of each key.
struct StreamNodeDiagnostics {
  std::mutex mutex;
  std::map<std::string, std::string> values;
  ros::Subscriber sub;
  void subscribe(ros::NodeHandle& nh, const std::string& node_name) {
    sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
        "/diagnostics", 1000, [this, name = node_name + ": stream"](const auto& m) {
          for (const auto& status : m->status) {
            if (status.name != name) continue;
            std::lock_guard<std::mutex> l(mutex);
            for (const auto& kv : status.values) values[kv.key] = kv.value;
          }
        });
  }
  std::string value(const std::string& key) {
    std::lock_guard<std::mutex> l(mutex);
    const auto it = values.find(key);
    return it == values.end() ? "" : it->second;
  }
  /// Waits (wall time) until `key` reads `want`.
  bool waitFor(const std::string& key, const std::string& want, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      if (value(key) == want) return true;
      ros::WallDuration(0.05).sleep();
    }
    return value(key) == want;
  }
};

/// A child process (argv[0] a path; stdout and stderr to `log`), stopped on destruction:
/// SIGINT (a ROS node shuts down cleanly), SIGKILL after 5 s.
class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& argv, const std::string& log) {
    std::vector<char*> args;  // built before fork: the child of a threaded process only execs
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
      }
      ::execvp(args[0], args.data());
      ::_exit(127);
    }
  }
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  /// Whether it still runs.
  bool running() {
    if (pid_ <= 0) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return false;
    }
    return true;
  }
  void stop() {
    if (!running()) return;
    ::kill(pid_, SIGINT);
    for (int i = 0; i < 50; ++i) {
      if (::waitpid(pid_, nullptr, WNOHANG) == pid_) {
        pid_ = -1;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

/// ppp_stream_node started by the test as `node_name`, reading `input` (a spec,
/// io/transport/byte_source_spec.h), publishing RTCM 3 on /gnss/receiver (what launch/live.launch
/// example b's nodes read), its diagnostics every 0.2 s. The test picks its ports at run
/// time, so the node cannot come from the launch file.
inline std::unique_ptr<ChildProcess> startStreamNode(const std::string& node_name, const std::string& input,
                                                     const std::string& log) {
  return std::make_unique<ChildProcess>(
      std::vector<std::string>{std::string(PPP_BIN_DIR) + "/ppp_stream_node", "__name:=" + node_name,
                               "_input:=" + input, "_format:=rtcm3", "_output_topic:=/gnss/receiver",
                               "_queue_size:=20000", "_diagnostic_period:=0.2"},
      log);
}

/// The ppp_solve reference of week-rollover-STR24.rtcm3 as live.launch runs the nodes
/// (config/ppp.yaml + config/live.yaml; test/rostest/live_str24.yaml: reference date,
/// broadcast only): `ppp_solve --rtcm F --ref-date 2018/07/14 --nav F --config config/live.yaml
/// --estimator both`.
inline PppSolveBoth pppSolveStr24Live(const std::string& rtcm, const std::string& tag) {
  const std::string atx = ppp::test::dataPath("antex/igs20_gps_satellites_trim.atx");
  return pppSolveBoth("--rtcm " + rtcm + " --ref-date 2018/07/14 --nav " + rtcm + " --atx " + atx + " --config " +
                          PPP_REPO_DIR + "/config/live.yaml",
                      tag);
}

/// The recording of the STR24 end-to-end tests (live_rtcm_launch, live_ntrip, live_serial):
/// GMSD, MSM7 + GPS/GLONASS ephemerides, across a week boundary.
inline std::string str24Recording() { return ppp::test::dataPath("streams/rtcm/week-rollover-STR24.rtcm3"); }

/// Their set-up: pppSolveStr24Live of str24Recording() into `offline`, which must have solved
/// more than 1000 EKF epochs (call through ASSERT_NO_FATAL_FAILURE).
inline void solveStr24Live(const std::string& tag, PppSolveBoth* offline) {
  *offline = pppSolveStr24Live(str24Recording(), tag);
  ASSERT_GT(offline->ekf.size(), 1000u) << "ppp_solve solved too few epochs of " << str24Recording();
}

/// Starts ppp_stream_node "receiver_stream" on `input` (startStreamNode; log `log`) into
/// `node`, its diagnostics into `stream`, and waits until it has connected (diagnostics
/// "connects" 1) and both PPP nodes subscribe /gnss/receiver, the TCPROS connections
/// settled (call through ASSERT_NO_FATAL_FAILURE).
inline void startConnectedStreamNode(ros::NodeHandle& nh, const std::string& input, const std::string& log,
                                     StreamNodeDiagnostics& stream, std::unique_ptr<ChildProcess>* node) {
  stream.subscribe(nh, "receiver_stream");
  *node = startStreamNode("receiver_stream", input, log);
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::WallTime::now() < until && (stream.value("connects").empty() || stream.value("connects") == "0"))
    ros::WallDuration(0.05).sleep();
  ASSERT_EQ(stream.value("connects"), "1") << "ppp_stream_node did not connect: " << stream.value("last error")
                                           << "\n" << ppp::test::readFileBytes(log);
  ASSERT_TRUE(waitForSubscriberCount("/gnss/receiver", 2, 30.0)) << "the PPP nodes do not subscribe /gnss/receiver";
  ros::WallDuration(1.0).sleep();  // the TCPROS connections settle
}

/// The stream node published all `frames` (its diagnostics, within 30 s).
inline void expectAllFramesPublished(StreamNodeDiagnostics& stream, std::size_t frames) {
  EXPECT_TRUE(stream.waitFor("frames published", std::to_string(frames), 30.0))
      << stream.value("frames published") << " of " << frames << " frames published";
}

/// The ending of the end-to-end tests through launch/live.launch: waits until both nodes
/// gave a fix at every ppp_solve epoch but perhaps the last (and went quiet), then
/// LiveLaunchOutputs::expectEqualTo.
inline void waitAndExpectEqualTo(LiveLaunchOutputs& out, const PppSolveBoth& offline, const std::string& what) {
  waitForFixes(out.ekf, offline.ekf.size() - 1, 60.0);
  waitForFixes(out.smoother, offline.smoother_filtered.size() - 1, 30.0);
  out.expectEqualTo(offline, what);
}

/// main() of a live rostest: gtest, ros::init as `node_name`, two spinner threads.
inline int liveRostestMain(int argc, char** argv, const std::string& node_name) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node_name);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}

}  // namespace ppp_ros::test
