// ppp_bag_solve: ppp_solve for a replay bag, offline (no master, no rosbag play:
// as fast as the CPU allows).
//
//   ppp_bag_solve BAG --out DIR [--name N] [--config YAML [YAML...]] [--estimator ekf|smoother|both]
//                 [--atx F [F...]] [--bia F] [--blq F] [--truth X Y Z | --truth-csv F]
//                 [--no-truth-path] [--no-timings] [--result JSON]
//
// Reads gnss/observations (GnssObservations) and gnss/corrections
// (PreciseCorrections) with the rosbag C++ API, through the nodes' conversions
// (ros/message_conversions.h) and the nodes' product assembly (ANTEX, Bias-SINEX,
// BLQ as ros.products; the stream's systems, clock centre and antenna model
// declared from its first batch, as PppNode does), and runs the core pipeline
// (PppPipeline: the same PppEpochProcessor per epoch as ppp_solve and the nodes)
// with the corrections as its ephemeris (CorrectionBuffer over every batch of the
// bag). Writes ppp_solve's outputs (app/ppp_solve_run.h) into DIR. The truth:
// --truth X Y Z (ECEF, m), or --truth-csv F (a trajectory: gps_week,
// seconds_of_week, x_m, y_m, z_m; app/replay_report.h readTruthCsv), else the
// bag's truth/path (a simulated flight's true antenna path) unless --no-truth-path.
// --result writes the figures a campaign records for the job (app/campaign_job.h).
// Ambiguity resolution (ambiguity_resolution.enabled): the batches' satellite
// biases (ar_bias_kind, satellites[].biases) go to the product assembly's PPP-AR
// gate, as in the nodes. Messages that cannot be read (a damaged payload) or do
// not convert are skipped and named (file, topic, message index, bag time) and
// counted, and the rest of the bag is used (ros/bag_reader.h); conversion issues
// are counted with their reason. The batches go through the coverage check of file
// products (ppp/pipeline/product_coverage.h): corrections that end before the
// observations or lack observed satellites are notes, corrections of another
// time or of none of the observed satellites are refused. Epochs and batches are taken in GNSS time order
// (rosbag reads in record time order, which a bag need not share with the GNSS
// times): how many were out of order is said. A folder, a file that is no bag, or
// a bag without index (a stopped recording: `rosbag reindex`) is refused naming it.
// Exit status: 0 solved, 1 failed (the reason on stderr), 2 usage.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nav_msgs/Path.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "ppp_bayes_tree/app/campaign_job.h"
#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/app/replay_report.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/ppp/pipeline/product_coverage.h"
#include "ppp_bayes_tree/ros/bag_reader.h"
#include "ppp_bayes_tree/ros/bag_writer.h"
#include "ppp_bayes_tree/ros/message_conversions.h"

namespace {

int usage(const std::string& why) {
  std::cerr << "ppp_bag_solve: " << why << "\n"
            << "usage: ppp_bag_solve BAG --out DIR [--name N] [--config YAML...] [--estimator "
            << ppp::registeredEstimatorNames("|") << '|' << ppp::kAllEstimators << "]\n"
            << "                     [--atx F...] [--bia F] [--blq F] [--truth X Y Z | --truth-csv F] [--no-truth-path]\n"
            << "                     [--no-timings] [--result JSON]\n";
  return 2;
}

/// Everything the pipeline needs from a bag, converted by the nodes' conversions.
struct BagContents {
  ppp::RinexObsHeader layout;         // the observation types of every epoch
  std::vector<ppp::ObsEpoch> epochs;  // in GNSS time order
  std::vector<ppp::CorrectionBatch> batches;  // in GNSS time order
  std::optional<ppp::StreamedProductInfo> streamed;  // from the first batch
  std::vector<ppp::SatelliteBiasBatch> ar_biases;   // the batches' biases for ambiguity resolution
  ppp::PhaseInformation ar_bias_kind = ppp::PhaseInformation::None;  // what the batches declare
  ppp::TruthTrajectory truth_path;  // truth/path (a simulated flight)
  ppp_ros::ConversionIssues issues;
  std::vector<std::string> problems;  // "BAG: gnss/observations message 12 (bag time ...): ..." (skipped)
  std::vector<std::string> order_notes;  // messages whose GNSS time is out of the bag's order
};

/// The reading state: the contents so far and the message of each epoch, kept
/// for the conversion again with the final layout.
struct BagReading {
  std::string path;
  BagContents c;
  std::vector<ppp_bayes_tree::GnssObservations::ConstPtr> converted;  // the message of each of c.epochs
  std::size_t layout_settled = 0;  // epochs before this index were converted with an earlier layout
};

void takeObservations(const rosbag::MessageInstance& m, std::size_t i, BagReading& r) {
  const std::string topic = ppp_ros::relativeBagTopic(m.getTopic());
  auto msg = m.instantiate<ppp_bayes_tree::GnssObservations>();  // throws for a damaged payload
  const auto place = [&] { return ppp_ros::bagMessagePlace(r.path, topic, i, m.getTime()); };
  if (!msg) return r.c.problems.push_back(place() + ": not a GnssObservations");
  ppp::ObsEpoch epoch;
  try {
    if (ppp_ros::fromMessage(*msg, r.c.layout, epoch, r.c.issues)) r.layout_settled = r.c.epochs.size() + 1;
    r.c.epochs.push_back(std::move(epoch));
    r.converted.push_back(msg);
  } catch (const std::invalid_argument& e) {
    r.c.problems.push_back(place() + ": " + e.what());
  }
}

void takeCorrections(const rosbag::MessageInstance& m, std::size_t i, BagReading& r) {
  const std::string topic = ppp_ros::relativeBagTopic(m.getTopic());
  auto msg = m.instantiate<ppp_bayes_tree::PreciseCorrections>();  // throws for a damaged payload
  const auto place = [&] { return ppp_ros::bagMessagePlace(r.path, topic, i, m.getTime()); };
  if (!msg) return r.c.problems.push_back(place() + ": not a PreciseCorrections");
  BagContents& c = r.c;
  try {
    ppp::CorrectionBatch batch = ppp_ros::fromMessage(*msg, c.issues);
    if (!c.streamed) c.streamed = ppp_ros::streamedProductInfo(*msg, batch);
    ppp::SatelliteBiasBatch biases = ppp_ros::biasesFromMessage(*msg, c.issues);
    if (!biases.biases.empty()) {
      c.ar_bias_kind = ppp_ros::phaseInformation(msg->ar_bias_kind);
      c.ar_biases.push_back(std::move(biases));
    }
    c.batches.push_back(std::move(batch));
  } catch (const std::invalid_argument& e) {
    c.problems.push_back(place() + ": " + e.what());
  }
}

void takeTruthPath(const rosbag::MessageInstance& m, ppp::TruthTrajectory& truth) {
  auto msg = m.instantiate<nav_msgs::Path>();
  if (!msg) return;
  for (const auto& p : msg->poses) {
    const ppp::GnssTime t = ppp_ros::fromUtcStamp(p.header.stamp);
    if (!truth.time.empty() && !(truth.time.back() < t)) continue;  // strictly increasing
    truth.time.push_back(t);
    truth.position_ecef_m.emplace_back(p.pose.position.x, p.pose.position.y, p.pose.position.z);
  }
}

/// How many items come after a later one (their GNSS time before the largest so
/// far), and the index of the first.
template <class T>
std::pair<std::size_t, std::size_t> outOfOrder(const std::vector<T>& items) {
  std::size_t count = 0, first = 0;
  for (std::size_t i = 1, latest = 0; i < items.size(); ++i) {
    if (items[i].time < items[latest].time) {
      if (count++ == 0) first = i;
    } else {
      latest = i;
    }
  }
  return {count, first};
}

/// Puts `items` in GNSS time order (stable: equal times keep the bag's order);
/// a note says how many were out of order. rosbag reads a bag in the order of
/// its record times, which need not be the order of the GNSS times the
/// messages carry (a bag written with other record times, or re-ordered).
template <class T>
void sortByGnssTime(std::vector<T>& items, const std::string& what, BagContents& c) {
  const auto [count, first] = outOfOrder(items);
  if (count == 0) return;
  c.order_notes.push_back(std::to_string(count) + " of " + std::to_string(items.size()) + " " + what +
                          " come after a later one in the bag (the first: number " + std::to_string(first) + ", " +
                          items[first].time.toString(ppp::TimeSystem::GPS, 1) +
                          " GPST): taken in GNSS time order");
  std::stable_sort(items.begin(), items.end(), [](const T& a, const T& b) { return a.time < b.time; });
}

/// Reads the bag once. The layout grows as new codes appear; the epochs converted
/// before its last change are converted again from their kept messages with the
/// final layout, so that every epoch's slices follow one header (as a RINEX file's).
/// A message that cannot be read or converted is skipped and named.
BagContents readBag(const std::string& path) {
  rosbag::Bag bag;
  ppp_ros::openBagForReading(bag, path);  // throws BagReadError naming the file
  const std::string obs_topic = ppp_ros::BagWriteOptions{}.observations_topic;
  const std::string corr_topic = ppp_ros::BagWriteOptions{}.corrections_topic;
  BagReading r;
  r.path = path;
  const auto take = [&](const rosbag::MessageInstance& m, std::size_t i) {
    const std::string topic = ppp_ros::relativeBagTopic(m.getTopic());
    if (topic == obs_topic) takeObservations(m, i, r);
    else if (topic == corr_topic) takeCorrections(m, i, r);
    else if (topic == ppp_ros::kTruthPathTopic && r.c.truth_path.empty()) takeTruthPath(m, r.c.truth_path);
  };
  ppp_ros::readBagMessages(bag, path, take, r.c.problems);
  bag.close();
  ppp_ros::ConversionIssues counted_once;  // the first conversion counted them
  for (std::size_t i = 0; i + 1 < r.layout_settled; ++i)
    ppp_ros::fromMessage(*r.converted[i], r.c.layout, r.c.epochs[i], counted_once);
  sortByGnssTime(r.c.epochs, "observation epochs", r.c);
  sortByGnssTime(r.c.batches, "correction batches", r.c);
  sortByGnssTime(r.c.ar_biases, "bias batches", r.c);
  return r.c;
}

struct Options {
  std::string bag, out, name, result, truth_csv;
  std::vector<std::string> config, atx;
  std::string bia, blq, estimator = std::string(ppp::kDefaultEstimator);
  std::optional<Eigen::Vector3d> truth;
  bool truth_path = true, timings = true;
};

/// The batches against the epochs, by the coverage check of file products
/// (product_coverage.h): their span, and the satellites they correct (position and
/// clock) against those observed of the systems processed. Corrections that end
/// early or lack satellites are notes; corrections of another time, or of none of
/// the observed satellites, are refused (std::runtime_error).
void checkBatchCoverage(const BagContents& bag, const std::string& path, const std::vector<ppp::GnssSystem>& systems,
                        std::vector<std::string>& notes) {
  const std::string name = ppp::fileBaseName(path);
  const ppp::ProductTimeSpan span{"corrections", name, bag.batches.front().time, bag.batches.back().time};
  ppp::applyCoverageFinding(ppp::checkProductCoverage(span, bag.epochs.front().time, bag.epochs.back().time), notes);
  ppp::ProductSatellites corrected{"corrections", name, {}};
  for (const auto& b : bag.batches)
    for (const auto& s : b.satellites)
      if (s.position_ecef_m && s.clock_bias_s) corrected.carried.insert(s.satellite);
  std::set<ppp::SatelliteId> observed;
  for (const auto& e : bag.epochs)
    for (const auto& s : e.satellites)
      if (std::find(systems.begin(), systems.end(), s.satellite.system) != systems.end()) observed.insert(s.satellite);
  ppp::applyCoverageFinding(ppp::checkSatelliteCoverage(corrected, observed), notes);
}

/// The pipeline over the bag's contents: the product assembly as the nodes make it
/// (ros.products + what the stream declares), the corrections as the ephemeris.
std::unique_ptr<ppp::PppPipeline> bagPipeline(const BagContents& bag, const Options& o, const ppp::PppConfig& config) {
  ppp::ProductAssemblyInputs in;
  in.atx = o.atx;
  if (!o.bia.empty()) in.bias = o.bia;
  if (!o.blq.empty()) in.blq = o.blq;
  ppp::ProductAssembly assembly = ppp::ProductAssembly::assemble(in, config);
  if (bag.streamed) assembly.declareStreamedProducts(*bag.streamed);
  // The batches' satellite biases to the assembly's PPP-AR gate, as the nodes hand theirs.
  auto stream_biases = std::make_shared<ppp::StreamBiasProvider>(std::numeric_limits<double>::infinity());
  for (const auto& b : bag.ar_biases) stream_biases->add(b);
  if (!stream_biases->empty() && bag.ar_bias_kind != ppp::PhaseInformation::None)
    assembly.acceptStreamedPhaseBiases(stream_biases.get(), bag.ar_bias_kind);
  std::cout << "ppp_bag_solve: " << assembly.arGate().text() << "\n";
  ppp::CorrectionBufferOptions buffer_options;
  buffer_options.history_s = std::numeric_limits<double>::infinity();  // every batch of the bag
  auto corrections = std::make_shared<ppp::CorrectionBuffer>(buffer_options);
  std::size_t refused = 0;  // duplicate batch times, or batches out of time order
  for (const auto& b : bag.batches) refused += corrections->add(b) != ppp::BatchAddResult::Added;
  if (refused > 0) std::cerr << "ppp_bag_solve: " << refused << " correction batches refused (repeated or out of order)\n";
  for (const auto& p : assembly.problems()) std::cerr << "ppp_bag_solve: products: " << p << "\n";
  ppp::PppProducts products = assembly.products(bag.layout.marker_name);
  products.ephemeris = corrections;
  if (assembly.phaseBiases() == stream_biases.get()) products.phase_biases = stream_biases;
  products.notes.push_back("orbits and clocks: " + std::to_string(bag.batches.size()) + " correction batches of " +
                           o.bag);
  checkBatchCoverage(bag, o.bag, assembly.config().signals.systems, products.notes);
  auto source = std::make_unique<ppp::InMemoryObservationSource>(bag.layout, bag.epochs, o.bag);
  return std::make_unique<ppp::PppPipeline>(std::move(source), std::move(products), assembly.config());
}

/// The moving truth: --truth-csv, else the bag's truth/path (unless --no-truth-path).
ppp::TruthTrajectory truthTrajectory(const BagContents& bag, const Options& o) {
  if (o.truth_csv.empty()) return o.truth_path ? bag.truth_path : ppp::TruthTrajectory{};
  ppp::ParseReport report(o.truth_csv);
  ppp::TruthTrajectory truth = ppp::readTruthCsv(o.truth_csv, report);
  if (!report.clean()) std::cerr << "ppp_bag_solve: truth " << report.summary();
  if (truth.empty()) throw std::runtime_error("no truth position in " + o.truth_csv);
  return truth;
}

std::optional<Options> parseArguments(int argc, char** argv, std::string& why) {
  Options o;
  std::vector<std::string>* list = nullptr;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) {
      if (list) list->push_back(a);
      else if (o.bag.empty()) o.bag = a;
      else return why = "unexpected argument " + a, std::nullopt;
      continue;
    }
    list = nullptr;
    if (a == "--config") { list = &o.config; continue; }
    if (a == "--atx") { list = &o.atx; continue; }
    if (a == "--no-truth-path") { o.truth_path = false; continue; }
    if (a == "--no-timings") { o.timings = false; continue; }
    if (a == "--truth") {
      if (i + 3 >= argc) return why = "--truth needs X Y Z", std::nullopt;
      try {
        o.truth = Eigen::Vector3d(std::stod(argv[i + 1]), std::stod(argv[i + 2]), std::stod(argv[i + 3]));
      } catch (const std::exception&) {
        return why = "bad --truth value", std::nullopt;
      }
      i += 3;
      continue;
    }
    if (i + 1 >= argc) return why = "missing value after " + a, std::nullopt;
    const std::string v = argv[++i];
    if (a == "--out") o.out = v;
    else if (a == "--name") o.name = v;
    else if (a == "--estimator") {
      if (!ppp::selectEstimators(v, &why)) return why = "--estimator: " + why, std::nullopt;
      o.estimator = v;
    }
    else if (a == "--bia") o.bia = v;
    else if (a == "--blq") o.blq = v;
    else if (a == "--result") o.result = v;
    else if (a == "--truth-csv") o.truth_csv = v;
    else return why = "unknown option " + a, std::nullopt;
  }
  if (o.bag.empty()) return why = "give the BAG", std::nullopt;
  if (o.out.empty()) return why = "--out DIR is required", std::nullopt;
  if (o.truth && !o.truth_csv.empty()) return why = "give --truth or --truth-csv, not both", std::nullopt;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  std::string why;
  const std::optional<Options> parsed = parseArguments(argc, argv, why);
  if (!parsed) return usage(why);
  const Options& o = *parsed;
  try {
    const BagContents bag = readBag(o.bag);
    if (bag.epochs.empty()) throw std::runtime_error(o.bag + ": no GnssObservations on gnss/observations");
    if (bag.batches.empty()) throw std::runtime_error(o.bag + ": no PreciseCorrections on gnss/corrections");
    std::cout << "ppp_bag_solve: " << o.bag << ": " << bag.epochs.size() << " observation epochs, "
              << bag.batches.size() << " correction batches"
              << (bag.truth_path.empty() ? "" : ", a truth path") << "\n";
    for (const auto& p : bag.problems) std::cerr << "ppp_bag_solve: skipped " << p << "\n";
    if (!bag.problems.empty())
      std::cerr << "ppp_bag_solve: skipped messages: " << bag.problems.size() << " (the rest of " << o.bag
                << " is used)\n";
    for (const auto& n : bag.order_notes) std::cerr << "ppp_bag_solve: " << o.bag << ": " << n << "\n";
    for (const auto& [reason, n] : bag.issues.counts)
      std::cerr << "ppp_bag_solve: " << n << " x " << reason << "\n";
    ppp::PppSolveRequest req;
    req.files.obs = o.bag;
    if (!o.config.empty()) req.config = ppp::loadPppConfig(o.config);
    req.estimator = o.estimator;
    req.truth_ecef_m = o.truth;
    const ppp::TruthTrajectory truth = o.truth ? ppp::TruthTrajectory{} : truthTrajectory(bag, o);
    if (!truth.empty()) req.truth_at = [&truth](const ppp::GnssTime& t) { return truth.at(t); };
    req.out_dir = o.out;
    req.name = o.name;
    req.write_timings = o.timings;
    req.make_pipeline = [&](const ppp::PppConfig& config) { return bagPipeline(bag, o, config); };
    const std::vector<ppp::PppSolveOutcome> runs = ppp::solvePppEstimators(req);
    for (const auto& out : runs) {
      std::cout << "=== estimator " << out.run.estimator << " ===\n" << ppp::formatRunReport(out.run);
      for (const auto& s : out.outputs) std::cout << "wrote " << s.csv_path << "\n";
    }
    if (!o.result.empty()) ppp::writeFileAtomically(o.result, ppp::campaignPppResultJson(runs.front()) + "\n");
    if (runs.front().run.epochs_solved == 0) throw std::runtime_error("no epoch solved from " + o.bag);
  } catch (const std::exception& e) {
    std::cerr << "ppp_bag_solve: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
