// ppp_bag_report: the comparison table of a replay, from the bag recorded by
// launch/compare.launch (record:=true) and the truth.
//
//   ppp_bag_report --bag RECORDED.bag (--truth-csv TRUTH.csv | --truth X,Y,Z) [--input REPLAYED.bag]
//                  [--ekf-ns /ekf] [--smoother-ns /smoother] [--window-min 15] [--out DIR] [--name NAME]
//
// Rows (app/replay_report.h, the core statistics ppp_solve prints):
//   EKF               <ekf>/ppp/status + <ekf>/ppp/fix (per epoch, ECEF from the NavSatFix)
//   smoother filtered <smoother>/ppp/status + <smoother>/ppp/fix
//   smoother smoothed the LAST <smoother>/ppp/path/smoothed message (the whole re-estimated
//                     trajectory), else the newest <smoother>/ppp/odometry/smoothed per epoch;
//                     map (ENU) poses go to ECEF through the node's datum, recovered from its
//                     ppp/fix + ppp/odometry/filtered pairs (mapDatumFromPair)
// PPP-AR: fixed share and time to first fix per row; an epoch is fixed when the
// node's ppp/fix of its stamp has NavSatStatus STATUS_GBAS_FIX (the smoothed row
// takes the smoother's epochs: the same graph with its held integers).
// Node figures: update time median/p99 (ppp/status update_time_s), epochs processed, and
// dropped = observation epochs of --input not processed (else the duplicate/out-of-order counts).
// A missing topic gives a clear line and the other rows are still printed. A damaged
// message is skipped and named (ros/bag_reader.h); a file that is no bag, or a bag
// without index, is refused naming it.
// Writes into --out (when given): NAME_ekf.csv, NAME_smoother_filtered.csv,
// NAME_smoother_smoothed.csv (the per-epoch format of ppp_solve, read by
// scripts/plot_solutions.py) and NAME_report.json.
// Exit: 0 all three rows; 3 some rows missing (the others printed); 1 none / error; 2 usage.
#include <sys/stat.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/NavSatFix.h>

#include "ppp_bayes_tree/PppStatus.h"
#include "ppp_bayes_tree/app/replay_report.h"
#include "ppp_bayes_tree/ros/bag_reader.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/time_system.h"

namespace {

constexpr std::int64_t kGpsEpochUnix_s = 315964800;  // 1980-01-06 00:00:00 UTC as POSIX seconds

int usage(const std::string& why) {
  std::cerr << "ppp_bag_report: " << why << "\n"
            << "usage: ppp_bag_report --bag RECORDED.bag (--truth-csv TRUTH.csv | --truth X,Y,Z) [--input REPLAYED.bag]\n"
            << "                      [--ekf-ns /ekf] [--smoother-ns /smoother] [--window-min 15] [--out DIR] [--name NAME]\n";
  return 2;
}

/// GPST of a UTC ROS stamp (inverse of ppp_ros::utcStamp: UTC + the leap seconds in force).
ppp::GnssTime gpstOfStamp(const ros::Time& stamp) {
  const ppp::GnssTime utc_as_gps = ppp::GnssTime::fromGpsSeconds(stamp.sec - kGpsEpochUnix_s, stamp.nsec * 1e-9);
  ppp::GnssTime t = utc_as_gps - utc_as_gps.offsetToSystem_s(ppp::TimeSystem::UTC);
  return utc_as_gps - t.offsetToSystem_s(ppp::TimeSystem::UTC);  // leap count at the GPST instant itself
}

std::string trimSlash(std::string s) {
  while (!s.empty() && s.front() == '/') s.erase(s.begin());
  while (!s.empty() && s.back() == '/') s.pop_back();
  return s;
}

std::optional<double> finite(double v) { return std::isfinite(v) ? std::optional<double>(v) : std::nullopt; }

Eigen::Matrix3d enuCovariance(const boost::array<double, 36>& c) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) m(r, k) = c[r * 6 + k];
  return m;
}

Eigen::Matrix3d ecefFromEnuAxes(const Eigen::Vector3d& at_ecef_m) {
  const ppp::Geodetic g = ppp::ecefToGeodetic(at_ecef_m);
  return ppp::rotationEnuFromEcef(g.latitude_rad, g.longitude_rad).transpose();
}

/// Everything one node published, read from the recorded bag.
struct NodeRecord {
  std::string ns;
  std::vector<ppp::ReplayStatusSample> status;
  std::vector<ppp::ReplayPositionSample> fixes;
  std::map<std::int64_t, Eigen::Vector3d> fix_by_stamp_ns;  // for the datum pairs
  std::vector<std::int64_t> status_stamp_ns;                 // of `status`, same order
  std::set<std::int64_t> carrier_fixed_stamp_ns;             // fixes with NavSatStatus STATUS_GBAS_FIX
  std::vector<std::pair<ros::Time, Eigen::Vector3d>> datums;  // (bag time, datum) from fix + filtered odometry
  std::size_t odometry_filtered = 0;
  nav_msgs::Path::ConstPtr last_smoothed_path;
  ros::Time last_smoothed_path_time;
  std::vector<std::pair<ros::Time, nav_msgs::Odometry::ConstPtr>> smoothed_odometry;

  std::optional<Eigen::Vector3d> datumAt(const ros::Time& bag_time) const {
    if (datums.empty()) return std::nullopt;
    Eigen::Vector3d d = datums.front().second;
    for (const auto& [t, v] : datums)
      if (t <= bag_time) d = v;
    return d;
  }
};

std::int64_t stampNs(const ros::Time& t) { return static_cast<std::int64_t>(t.sec) * 1000000000LL + t.nsec; }

void readNode(const rosbag::MessageInstance& m, const std::string& rel, NodeRecord& n) {
  if (rel == "ppp/status") {
    const auto s = m.instantiate<ppp_bayes_tree::PppStatus>();
    if (!s) return;
    ppp::ReplayStatusSample x;
    x.time = gpstOfStamp(s->header.stamp);
    x.solved = s->solution_state != ppp_bayes_tree::PppStatus::NO_SOLUTION;
    x.satellites_used = s->satellites_used;
    x.satellites_rejected = s->satellites_rejected;
    x.zwd_m = finite(s->zwd_m);
    x.receiver_clock_m = finite(s->receiver_clock_m);
    // An empty epoch's status has no update (update_time_s stays 0 and no epoch was processed).
    if (s->reason != "empty epoch") x.update_time_s = s->update_time_s;
    x.epochs_processed = s->epochs_processed;
    x.epochs_duplicate = s->epochs_duplicate;
    x.epochs_out_of_order = s->epochs_out_of_order;
    x.estimator_resets = s->estimator_resets;
    n.status.push_back(x);
    n.status_stamp_ns.push_back(stampNs(s->header.stamp));
  } else if (rel == "ppp/fix") {
    const auto f = m.instantiate<sensor_msgs::NavSatFix>();
    if (!f || !std::isfinite(f->latitude) || !std::isfinite(f->longitude) || !std::isfinite(f->altitude)) return;
    ppp::ReplayPositionSample p;
    p.time = gpstOfStamp(f->header.stamp);
    p.position_ecef_m = ppp::geodeticToEcef(
        ppp::Geodetic{f->latitude * ppp::kDegToRad, f->longitude * ppp::kDegToRad, f->altitude});
    if (f->position_covariance_type != sensor_msgs::NavSatFix::COVARIANCE_TYPE_UNKNOWN) {
      Eigen::Matrix3d c;  // ENU at the fix (REP-145)
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) c(r, k) = f->position_covariance[r * 3 + k];
      const Eigen::Matrix3d a = ecefFromEnuAxes(p.position_ecef_m);
      p.covariance_ecef_m2 = a * c * a.transpose();
    }
    n.fixes.push_back(p);
    n.fix_by_stamp_ns[stampNs(f->header.stamp)] = p.position_ecef_m;
    if (f->status.status == sensor_msgs::NavSatStatus::STATUS_GBAS_FIX) n.carrier_fixed_stamp_ns.insert(stampNs(f->header.stamp));
  } else if (rel == "ppp/odometry/filtered") {
    const auto o = m.instantiate<nav_msgs::Odometry>();
    if (!o) return;
    if (m.instantiate<nav_msgs::Odometry>()) ++n.odometry_filtered;  // paired with the fixes afterwards
  } else if (rel == "ppp/path/smoothed") {
    const auto p = m.instantiate<nav_msgs::Path>();
    if (p && m.getTime() >= n.last_smoothed_path_time) {
      n.last_smoothed_path = p;
      n.last_smoothed_path_time = m.getTime();
    }
  } else if (rel == "ppp/odometry/smoothed") {
    const auto o = m.instantiate<nav_msgs::Odometry>();
    if (o) n.smoothed_odometry.emplace_back(m.getTime(), o);
  }
}

/// Marks the status epochs whose fix says carrier-phase fixed (PPP-AR: the nodes
/// publish NavSatStatus STATUS_GBAS_FIX for a solution on held integer ambiguities,
/// as ROS GNSS drivers do for carrier-fixed RTK; doc/ros_interface.md).
void markFixedEpochs(NodeRecord& n) {
  for (std::size_t i = 0; i < n.status.size() && i < n.status_stamp_ns.size(); ++i)
    n.status[i].ambiguities_fixed = n.carrier_fixed_stamp_ns.count(n.status_stamp_ns[i]) > 0;
}

/// The node's map datums: each filtered odometry paired with the fix of the same stamp
/// (a second pass: the node publishes the odometry just before the fix).
void pairDatums(const rosbag::Bag& bag, const std::string& topic, NodeRecord& n) {
  if (n.fix_by_stamp_ns.empty()) return;
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{topic, "/" + topic}));
  for (const auto& m : view) {
    nav_msgs::Odometry::ConstPtr o;
    try {
      o = m.instantiate<nav_msgs::Odometry>();
    } catch (const std::exception&) {  // damaged: named by the first pass
      continue;
    }
    if (!o) continue;
    const auto it = n.fix_by_stamp_ns.find(stampNs(o->header.stamp));
    if (it == n.fix_by_stamp_ns.end()) continue;
    const Eigen::Vector3d enu(o->pose.pose.position.x, o->pose.pose.position.y, o->pose.pose.position.z);
    n.datums.emplace_back(m.getTime(), ppp::mapDatumFromPair(it->second, enu));
  }
}

/// The row of one solution: the node's status epochs with their positions, matched to
/// the truth; solved epochs without a position are left out and said on stderr.
ppp::ReplayReportRow rowFromPositions(const std::string& label, const std::string& key,
                                      const std::vector<ppp::ReplayStatusSample>& status,
                                      std::vector<ppp::ReplayPositionSample> positions, const std::string& position_kind,
                                      const ppp::TruthTrajectory& truth, const ppp::StatisticsOptions& opt,
                                      const std::optional<ppp::NodeFigures>& fig) {
  const ppp::AssembledSolution a = ppp::assembleReplaySolution(status, std::move(positions));
  if (a.solved_without_position)
    std::cerr << "ppp_bag_report: " << label << ": " << a.solved_without_position << " solved epochs without "
              << position_kind << " (left out)\n";
  ppp::ReplayReportRow row = ppp::buildReplayReportRow(label, key, a.epochs, truth, opt);
  row.node = fig;
  return row;
}

ppp::ReplayReportRow filteredRow(const std::string& label, const std::string& key, const NodeRecord& n,
                                 const ppp::TruthTrajectory& truth, const ppp::StatisticsOptions& opt,
                                 const std::optional<ppp::NodeFigures>& fig) {
  if (n.status.empty() && n.fixes.empty())
    return ppp::missingReplayReportRow(label, key, "no /" + n.ns + "/ppp/status nor /" + n.ns +
                                                       "/ppp/fix in the bag (node not running, or not recorded?)");
  if (n.fixes.empty())
    return ppp::missingReplayReportRow(label, key, "no /" + n.ns + "/ppp/fix in the bag (" +
                                                       std::to_string(n.status.size()) + " status messages)");
  return rowFromPositions(label, key, n.status, n.fixes, "a fix in the bag", truth, opt, fig);
}

ppp::ReplayReportRow smoothedRow(const NodeRecord& n, const ppp::TruthTrajectory& truth,
                                 const ppp::StatisticsOptions& opt, const std::optional<ppp::NodeFigures>& fig) {
  const std::string label = "smoother smoothed", key = "smoother_smoothed";
  std::vector<ppp::ReplayPositionSample> pos;
  auto toEcef = [&](const std::string& frame, const ros::Time& bag_time, const Eigen::Vector3d& v,
                    Eigen::Vector3d& out, Eigen::Matrix3d* axes) -> bool {
    if (frame == "earth") {  // poses already in ECEF
      out = v;
      if (axes) axes->setIdentity();
      return true;
    }
    const auto d = n.datumAt(bag_time);
    if (!d) return false;
    out = ppp::enuToEcef(v, *d);
    if (axes) *axes = ecefFromEnuAxes(*d);
    return true;
  };
  std::string source;
  if (n.last_smoothed_path) {
    source = "path";
    for (const auto& p : n.last_smoothed_path->poses) {
      const std::string frame = p.header.frame_id.empty() ? n.last_smoothed_path->header.frame_id : p.header.frame_id;
      ppp::ReplayPositionSample s;
      s.time = gpstOfStamp(p.header.stamp);
      if (!toEcef(frame, n.last_smoothed_path_time,
                  Eigen::Vector3d(p.pose.position.x, p.pose.position.y, p.pose.position.z), s.position_ecef_m, nullptr))
        return ppp::missingReplayReportRow(label, key, "no map datum for /" + n.ns +
                                                           "/ppp/path/smoothed (needs ppp/fix and ppp/odometry/filtered)");
      pos.push_back(s);
    }
  } else if (!n.smoothed_odometry.empty()) {
    source = "odometry";
    for (const auto& [bag_time, o] : n.smoothed_odometry) {
      ppp::ReplayPositionSample s;
      s.time = gpstOfStamp(o->header.stamp);
      Eigen::Matrix3d axes;
      const Eigen::Vector3d enu(o->pose.pose.position.x, o->pose.pose.position.y, o->pose.pose.position.z);
      if (!toEcef(o->header.frame_id, bag_time, enu, s.position_ecef_m, &axes))
        return ppp::missingReplayReportRow(label, key, "no map datum for /" + n.ns +
                                                           "/ppp/odometry/smoothed (needs ppp/fix and ppp/odometry/filtered)");
      const Eigen::Matrix3d c = enuCovariance(o->pose.covariance);
      if (c.allFinite()) s.covariance_ecef_m2 = axes * c * axes.transpose();
      pos.push_back(s);
    }
  } else {
    return ppp::missingReplayReportRow(label, key, "neither /" + n.ns + "/ppp/path/smoothed nor /" + n.ns +
                                                       "/ppp/odometry/smoothed in the bag (smoother node not running, "
                                                       "or not recorded?)");
  }
  return rowFromPositions(label, key, n.status, std::move(pos), "a smoothed pose (from the " + source + ")", truth,
                          opt, fig);
}

bool writeText(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  f.close();
  if (!f) std::cerr << "ppp_bag_report: cannot write " << path << "\n";
  return static_cast<bool>(f);
}

}  // namespace

int main(int argc, char** argv) {
  std::string bag_path, input_path, truth_csv, truth_point, out_dir, name = "replay";
  std::string ekf_ns = "ekf", smoother_ns = "smoother";
  double window_min = 15.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage("missing value after " + a);
    const std::string v = argv[++i];
    if (a == "--bag") bag_path = v;
    else if (a == "--input") input_path = v;
    else if (a == "--truth-csv") truth_csv = v;
    else if (a == "--truth") truth_point = v;
    else if (a == "--ekf-ns") ekf_ns = trimSlash(v);
    else if (a == "--smoother-ns") smoother_ns = trimSlash(v);
    else if (a == "--out") out_dir = v;
    else if (a == "--name") name = v;
    else if (a == "--window-min") {
      try {
        window_min = std::stod(v);
      } catch (const std::exception&) {
        return usage("bad --window-min " + v);
      }
      if (!(window_min > 0.0)) return usage("--window-min must be > 0");
    } else return usage("unknown option " + a);
  }
  if (bag_path.empty()) return usage("--bag RECORDED.bag is required");
  if (truth_csv.empty() == truth_point.empty()) return usage("give exactly one of --truth-csv FILE and --truth X,Y,Z");

  try {
    // Truth.
    ppp::TruthTrajectory truth;
    if (!truth_point.empty()) {
      double x, y, z;
      char c1, c2;
      std::istringstream in(truth_point);
      if (!(in >> x >> c1 >> y >> c2 >> z) || c1 != ',' || c2 != ',')
        return usage("--truth wants X,Y,Z in metres (ECEF), got " + truth_point);
      truth = ppp::TruthTrajectory::fixedPoint(Eigen::Vector3d(x, y, z));
    } else {
      ppp::ParseReport report;
      truth = ppp::readTruthCsv(truth_csv, report);
      if (!report.clean()) std::cerr << "ppp_bag_report: truth " << report.summary();
      if (truth.empty()) {
        std::cerr << "ppp_bag_report: no truth position in " << truth_csv << "\n";
        return 1;
      }
    }

    // Observation epochs replayed (for "dropped").
    std::optional<std::size_t> input_epochs;
    if (!input_path.empty()) {
      rosbag::Bag in;
      ppp_ros::openBagForReading(in, input_path);
      rosbag::View view(in, rosbag::TopicQuery(std::vector<std::string>{"gnss/observations", "/gnss/observations"}));
      input_epochs = view.size();
    }

    // Recorded outputs; a damaged message is skipped and named.
    rosbag::Bag bag;
    ppp_ros::openBagForReading(bag, bag_path);
    NodeRecord ekf, smoother;
    ekf.ns = ekf_ns;
    smoother.ns = smoother_ns;
    std::set<std::string> topics;
    std::vector<std::string> skipped;
    const auto take = [&](const rosbag::MessageInstance& m, std::size_t) {
      const std::string topic = trimSlash(m.getTopic());
      topics.insert(topic);
      for (NodeRecord* n : {&ekf, &smoother}) {
        const std::string prefix = n->ns + "/";
        if (topic.rfind(prefix, 0) == 0) readNode(m, topic.substr(prefix.size()), *n);
      }
    };
    const std::size_t messages = ppp_ros::readBagMessages(bag, bag_path, take, skipped);
    for (const auto& p : skipped) std::cerr << "ppp_bag_report: skipped " << p << "\n";
    if (!skipped.empty()) std::cerr << "ppp_bag_report: skipped messages: " << skipped.size() << "\n";
    markFixedEpochs(ekf);
    markFixedEpochs(smoother);
    pairDatums(bag, ekf_ns + "/ppp/odometry/filtered", ekf);
    pairDatums(bag, smoother_ns + "/ppp/odometry/filtered", smoother);
    std::cout << "ppp_bag_report: " << bag_path << ": " << messages << " messages on " << topics.size()
              << " topics; /" << ekf_ns << ": " << ekf.status.size() << " status, " << ekf.fixes.size() << " fixes; /"
              << smoother_ns << ": " << smoother.status.size() << " status, " << smoother.fixes.size() << " fixes, "
              << (smoother.last_smoothed_path ? smoother.last_smoothed_path->poses.size() : 0)
              << " poses in the last smoothed path, " << smoother.smoothed_odometry.size() << " smoothed odometry\n";

    ppp::StatisticsOptions opt;
    opt.convergence_window_s = window_min * 60.0;
    std::optional<ppp::NodeFigures> ekf_fig, smoother_fig;
    if (!ekf.status.empty()) ekf_fig = ppp::replayNodeFigures(ekf_ns, ekf.status, input_epochs);
    if (!smoother.status.empty()) smoother_fig = ppp::replayNodeFigures(smoother_ns, smoother.status, input_epochs);
    std::vector<ppp::ReplayReportRow> rows;
    rows.push_back(filteredRow("EKF", "ekf", ekf, truth, opt, ekf_fig));
    rows.push_back(filteredRow("smoother filtered", "smoother_filtered", smoother, truth, opt, smoother_fig));
    rows.push_back(smoothedRow(smoother, truth, opt, smoother_fig));

    std::cout << "\n" << ppp::formatReplayReport(rows);
    if (input_epochs) std::cout << "(node epochs: dropped = observation epochs in the replayed bag (" << *input_epochs
                                << ") not processed by the node)\n";

    if (!out_dir.empty()) {
      ::mkdir(out_dir.c_str(), 0755);
      std::cout << "written:";
      for (const auto& r : rows) {
        if (!r.missing.empty()) continue;
        const std::string path = out_dir + "/" + name + "_" + r.key + ".csv";
        if (writeText(path, ppp::replayReportCsv(r))) std::cout << "\n  " << path;
      }
      const std::string json = out_dir + "/" + name + "_report.json";
      if (writeText(json, ppp::replayReportJson(rows))) std::cout << "\n  " << json;
      std::cout << "\n";
    }
    std::size_t present = 0;
    for (const auto& r : rows) present += r.missing.empty();
    return present == rows.size() ? 0 : present > 0 ? 3 : 1;
  } catch (const rosbag::BagException& e) {
    std::cerr << "ppp_bag_report: bag: " << e.what() << "\n";
  } catch (const std::exception& e) {  // ParseError, FileOpenError (name the file and line) and the rest
    std::cerr << "ppp_bag_report: " << e.what() << "\n";
  }
  return 1;
}
