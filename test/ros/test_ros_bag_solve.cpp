// ppp_bag_solve (src/ros/tools/ppp_bag_solve.cpp) and bag jobs of ppp_campaign,
// on a short simulated survey flight (no data needed).
//
// The reference: `ppp_simulate --out DIR --bag BAG` writes ONE flight both as
// RINEX + SP3/CLK files and as a replay bag (gnss/observations converted from the
// same epochs, losslessly; gnss/corrections sampled from the same precise
// products). ppp_solve on the files and ppp_bag_solve on the bag run the same core
// pipeline (PppPipeline: PppEpochProcessor per epoch, the estimator), only the
// inputs differ in form: the observations are equal after the message round trip,
// and the correction stream's interpolation of the batches reproduces the SP3/CLK
// interpolation at the 1 mm level (the nodes, which use the same conversions and
// correction buffer, equal ppp_solve within 1 mm: rostest ar_esbc_bag). So each
// epoch's position must agree within 1 mm. The same holds with ambiguity
// resolution on real data (ESBC, below; skipped without the shared data).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>

#include <functional>

#include "ppp_bayes_tree/GnssObservations.h"
#include "ppp_bayes_tree/PreciseCorrections.h"

#include "test_support.h"

namespace {

namespace fs = std::filesystem;

const std::string kBin = PPP_BIN_DIR;
const std::string kRepo = PPP_REPO_DIR;
const std::string kConfigs = kRepo + "/config/ppp.yaml " + kRepo + "/config/ppp_simulated.yaml";

int run(const std::string& cmd) { return std::system((cmd + " > /dev/null 2>&1").c_str()); }

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream is(line);
  while (std::getline(is, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

/// A CSV as rows of named cells.
std::vector<std::map<std::string, std::string>> readCsv(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  const auto header = split(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const auto cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

/// A figure of the "all_epochs" statistics of a summary JSON (NaN when absent).
double allEpochsFigure(const std::string& json, const std::string& key) {
  const std::size_t all = json.find("\"all_epochs\"");
  if (all == std::string::npos) return std::nan("");
  const std::size_t at = json.find("\"" + key + "\": ", all);
  if (at == std::string::npos) return std::nan("");
  return std::stod(json.substr(at + key.size() + 4));
}

class BagSolve : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("ppp_bag_solve_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "bags");
    // Two 3-minute survey flights (seeds 5 and 6); the first also as files.
    for (const auto& [seed, name] : {std::make_pair(5, "a"), std::make_pair(6, "b")}) {
      const std::string files = seed == 5 ? " --out " + (dir_ / "files").string() : "";
      const std::string cmd = kBin + "/ppp_simulate --profile survey --duration-min 3 --seed " + std::to_string(seed) +
                              files + " --bag " + (dir_ / "bags" / (std::string("flight_") + name + ".bag")).string();
      ASSERT_EQ(run(cmd), 0) << cmd;
    }
    // The simulation's antenna corrections are off (config/ppp_simulated.yaml): the
    // ANTEX ppp_solve requires holds no antenna.
    std::ofstream(dir_ / "empty.atx") << "     1.4            M                                       ANTEX VERSION / SYST\n"
                                      << "A                                                           PCV TYPE / REFANT\n"
                                      << "                                                            END OF HEADER\n";
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  static fs::path dir_;
};
fs::path BagSolve::dir_;

TEST_F(BagSolve, PositionsEqualPppSolveOnTheSameFlightWithin1mm) {
  const fs::path files = dir_ / "files", ref = dir_ / "ref", out = dir_ / "bag_out";
  std::string obs;
  for (const auto& e : fs::directory_iterator(files))
    if (e.path().extension() == ".obs") obs = e.path().string();
  ASSERT_FALSE(obs.empty());
  const std::string solve = kBin + "/ppp_solve --obs " + obs + " --sp3 " + (files / "products.sp3").string() +
                            " --clk " + (files / "products.clk").string() + " --atx " + (dir_ / "empty.atx").string() +
                            " --config " + kConfigs + " --name sim --out " + ref.string();
  ASSERT_EQ(run(solve), 0) << solve;
  const std::string bag_solve = kBin + "/ppp_bag_solve " + (dir_ / "bags" / "flight_a.bag").string() + " --config " +
                                kConfigs + " --name sim --out " + out.string();
  ASSERT_EQ(run(bag_solve), 0) << bag_solve;

  const auto a = readCsv(ref / "sim_ekf.csv"), b = readCsv(out / "sim_ekf.csv");
  ASSERT_EQ(a.size(), 181u) << "3 min at 1 Hz, both ends";
  ASSERT_EQ(a.size(), b.size());
  std::size_t compared = 0;
  double worst_m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].at("time_gpst"), b[i].at("time_gpst")) << "epoch " << i;
    ASSERT_EQ(a[i].at("x_m").empty(), b[i].at("x_m").empty()) << "solved in one and not the other at epoch " << i;
    if (a[i].at("x_m").empty()) continue;
    double d2 = 0.0;
    for (const char* k : {"x_m", "y_m", "z_m"}) d2 += std::pow(std::stod(a[i].at(k)) - std::stod(b[i].at(k)), 2);
    worst_m = std::max(worst_m, std::sqrt(d2));
    ++compared;
  }
  EXPECT_GT(compared, 150u);
  EXPECT_LE(worst_m, 1e-3) << "largest 3D difference ppp_bag_solve - ppp_solve over " << compared << " epochs";
  // The bag's truth/path gives the statistics (ppp_solve here had no truth).
  // The same truth from the simulator's truth CSV gives the same statistics.
  const std::string summary = readText(out / "sim_ekf_summary.json");
  EXPECT_NE(summary.find("\"statistics\""), std::string::npos) << summary.substr(0, 400);
  const fs::path with_csv = dir_ / "bag_out_csv";
  ASSERT_EQ(run(bag_solve + " --no-truth-path --truth-csv " + (files / "truth.csv").string() + " --out " +
                with_csv.string()),
            0);
  const std::string csv_summary = readText(with_csv / "sim_ekf_summary.json");
  EXPECT_EQ(allEpochsFigure(csv_summary, "count"), 181.0);
  EXPECT_NEAR(allEpochsFigure(csv_summary, "mean_m"), allEpochsFigure(summary, "mean_m"), 1e-4)
      << "truth.csv holds positions to 0.1 mm";
}

// Integer ambiguity resolution from the batches' biases: the first 2 h of ESBC
// 2020-177 made into a bag by ppp_to_bag from the GRG products (integer-recovery
// clocks: every batch carries the wide-lane satellite biases of the clock header),
// against ppp_solve on the same 2 h of the files with the same configuration (the
// rostest ar_esbc_bag's: the nodes equal ppp_solve there). Both estimators: the
// same fix state at every epoch, positions within 1 mm.
TEST_F(BagSolve, AmbiguityResolutionFromTheBatchesBiasesEqualsPppSolve) {
  PPP_REQUIRE_SHARED_DATA();
  const std::string esbc = ppp::test::dataPath("esbc-2020-177/");
  const std::string obs = esbc + "ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz";
  const std::string products = " --sp3 " + esbc + "GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz --clk " + esbc +
                               "GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz";
  const std::string atx = " --atx " + ppp::test::dataPath("antex/igs14_2178_satellites.atx") + " " +
                          ppp::test::dataPath("antex/igs05_esbc_receiver_trim.atx");
  const std::string config = " --config " + kRepo + "/config/ppp.yaml " + kRepo + "/test/rostest/ar_esbc.yaml";
  const fs::path bag = dir_ / "esbc_2h.bag", ref = dir_ / "esbc_ref", out = dir_ / "esbc_bag";
  ASSERT_EQ(run(kBin + "/ppp_to_bag --obs " + obs + products + " --max-epochs 240 --out " + bag.string()), 0);
  ASSERT_EQ(run(kBin + "/ppp_solve --obs " + obs + products + atx + config +
                " --end \"2020/06/25 02:00:00\" --estimator both --name e --out " + ref.string()),
            0);
  ASSERT_EQ(run(kBin + "/ppp_bag_solve " + bag.string() + atx + config + " --estimator both --name e --out " +
                out.string()),
            0);
  for (const char* tag : {"ekf", "smoother_filtered", "smoother_smoothed"}) {
    const auto a = readCsv(ref / ("e_" + std::string(tag) + ".csv"));
    const auto b = readCsv(out / ("e_" + std::string(tag) + ".csv"));
    ASSERT_EQ(a.size(), 240u) << tag;
    ASSERT_EQ(b.size(), a.size()) << tag;
    std::size_t fixed = 0;
    double worst_m = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].at("time_gpst"), b[i].at("time_gpst"));
      EXPECT_EQ(a[i].at("status"), b[i].at("status")) << tag << " epoch " << i;
      fixed += a[i].at("status") == "ppp-fixed";
      if (a[i].at("x_m").empty() || b[i].at("x_m").empty()) continue;
      double d2 = 0.0;
      for (const char* k : {"x_m", "y_m", "z_m"}) d2 += std::pow(std::stod(a[i].at(k)) - std::stod(b[i].at(k)), 2);
      worst_m = std::max(worst_m, std::sqrt(d2));
    }
    EXPECT_GT(fixed, 150u) << tag << ": ppp_solve fixes most of the 2 h (first fix after about 16 min)";
    EXPECT_LE(worst_m, 1e-3) << tag;
  }
}

TEST_F(BagSolve, RefusesAMissingBagAndABagWithoutGnssTopics) {
  const auto stderrOf = [&](const std::string& args, int& status) {
    const fs::path err = dir_ / "stderr.txt";
    status = WEXITSTATUS(std::system((kBin + "/ppp_bag_solve " + args + " > /dev/null 2> " + err.string()).c_str()));
    return readText(err);
  };
  int status = 0;
  const std::string missing = (dir_ / "nope.bag").string();
  EXPECT_NE(stderrOf(missing + " --out " + (dir_ / "x").string(), status).find(missing), std::string::npos);
  EXPECT_EQ(status, 1);
  const std::string empty = (dir_ / "empty.bag").string();
  {
    rosbag::Bag bag(empty, rosbag::bagmode::Write);
    std_msgs::String note;
    note.data = "no GNSS here";
    bag.write("notes", ros::Time(1e9), note);
  }
  EXPECT_NE(stderrOf(empty + " --out " + (dir_ / "x").string(), status).find(empty + ": no GnssObservations"),
            std::string::npos);
  EXPECT_EQ(status, 1);
  stderrOf("--out " + (dir_ / "x").string(), status);
  EXPECT_EQ(status, 2) << "no bag: usage";
}

/// ppp_bag_solve's exit status, with its stderr in `err`.
int bagSolve(const std::string& args, const fs::path& err_file, std::string& err) {
  const int status = std::system((kBin + "/ppp_bag_solve " + args + " > /dev/null 2> " + err_file.string()).c_str());
  err = readText(err_file);
  return WEXITSTATUS(status);
}

/// The bytes of the file.
std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_F(BagSolve, DamagedObservationMessageIsSkippedNamedAndTheRestSolved) {
  // flight_a.bag (uncompressed) with the payload of gnss/observations message 10
  // damaged: its header.frame_id length set to 2^31 - 1 (rosbag: "Buffer Overrun").
  const fs::path original = dir_ / "bags" / "flight_a.bag", damaged = dir_ / "damaged.bag";
  std::string bytes = readBytes(original);
  std::string payload;
  {
    rosbag::Bag bag(original.string(), rosbag::bagmode::Read);
    std::size_t i = 0;
    for (const auto& m : rosbag::View(bag, rosbag::TopicQuery("gnss/observations"))) {
      if (i++ != 10) continue;
      const auto msg = m.instantiate<ppp_bayes_tree::GnssObservations>();
      ASSERT_TRUE(msg);
      payload.resize(ros::serialization::serializationLength(*msg));
      ros::serialization::OStream os(reinterpret_cast<std::uint8_t*>(&payload[0]), payload.size());
      ros::serialization::serialize(os, *msg);
      break;
    }
  }
  ASSERT_FALSE(payload.empty());
  const std::size_t at = bytes.find(payload);
  ASSERT_NE(at, std::string::npos) << "the message's payload in the bag";
  ASSERT_EQ(bytes.find(payload, at + 1), std::string::npos) << "once";
  const std::size_t frame_id_length = at + 4 + 8;  // after header.seq and header.stamp
  bytes.replace(frame_id_length, 4, std::string("\xff\xff\xff\x7f", 4));
  std::ofstream(damaged, std::ios::binary) << bytes;

  std::string err;
  const fs::path out = dir_ / "damaged_out";
  ASSERT_EQ(bagSolve(damaged.string() + " --config " + kConfigs + " --name sim --out " + out.string(),
                     dir_ / "damaged.txt", err),
            0)
      << err;
  EXPECT_NE(err.find(damaged.string() + ": gnss/observations message 10 (bag time "), std::string::npos) << err;
  EXPECT_NE(err.find("cannot be read: Buffer Overrun"), std::string::npos) << err;
  EXPECT_NE(err.find("skipped messages: 1 (the rest of " + damaged.string() + " is used)"), std::string::npos) << err;
  EXPECT_EQ(readCsv(out / "sim_ekf.csv").size(), 180u) << "181 epochs, one skipped";
}

TEST_F(BagSolve, BagsThatCannotBeOpenedAreNamedWithWhatToDo) {
  std::string err;
  const fs::path text = dir_ / "notes.bag", folder = dir_ / "folder.bag", cut = dir_ / "cut.bag";
  std::ofstream(text) << "these are notes, not a bag\n";
  fs::create_directories(folder);
  const std::string bytes = readBytes(dir_ / "bags" / "flight_a.bag");
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);  // a recording cut short
  const std::string out = " --out " + (dir_ / "never").string();
  EXPECT_EQ(bagSolve(text.string() + out, dir_ / "open.txt", err), 1);
  EXPECT_NE(err.find(text.string() + ": not a bag file"), std::string::npos) << err;
  EXPECT_EQ(bagSolve(folder.string() + out, dir_ / "open.txt", err), 1);
  EXPECT_NE(err.find(folder.string() + ": is a directory"), std::string::npos) << err;
  EXPECT_EQ(bagSolve(cut.string() + out, dir_ / "open.txt", err), 1);
  EXPECT_NE(err.find(cut.string() + ": "), std::string::npos) << err;
  EXPECT_NE(err.find("rosbag reindex " + cut.string()), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "never"));
}

TEST_F(BagSolve, RecordsInReverseOrderAreSolvedInGnssTimeOrder) {
  // The messages of flight_a.bag written last first, with record times that
  // increase: rosbag reads them newest epoch first.
  const fs::path original = dir_ / "bags" / "flight_a.bag", reversed = dir_ / "reversed.bag";
  {
    rosbag::Bag in(original.string(), rosbag::bagmode::Read);
    std::vector<rosbag::MessageInstance> messages;
    for (const auto& m : rosbag::View(in)) messages.push_back(m);
    rosbag::Bag out(reversed.string(), rosbag::bagmode::Write);
    ros::Time record_time(1e9);
    for (auto m = messages.rbegin(); m != messages.rend(); ++m) {
      out.write(m->getTopic(), record_time, *m, m->getConnectionHeader());
      record_time += ros::Duration(0.001);
    }
  }
  const std::string args = " --config " + kConfigs + " --name sim --no-timings --out ";
  std::string err;
  ASSERT_EQ(bagSolve(original.string() + args + (dir_ / "forward").string(), dir_ / "fwd.txt", err), 0) << err;
  ASSERT_EQ(bagSolve(reversed.string() + args + (dir_ / "reverse").string(), dir_ / "rev.txt", err), 0) << err;
  EXPECT_NE(err.find("180 of 181 observation epochs come after a later one in the bag"), std::string::npos) << err;
  const std::string forward = readText(dir_ / "forward" / "sim_ekf.csv");
  EXPECT_EQ(readCsv(dir_ / "reverse" / "sim_ekf.csv").size(), 181u);
  EXPECT_TRUE(readText(dir_ / "reverse" / "sim_ekf.csv") == forward) << "every epoch solved, as from the ordered bag";
}

/// flight_a.bag with each gnss/corrections message passed through `edit` (false: dropped).
void writeEditedCorrections(const fs::path& original, const fs::path& edited,
                            const std::function<bool(ppp_bayes_tree::PreciseCorrections&)>& edit) {
  rosbag::Bag in(original.string(), rosbag::bagmode::Read);
  rosbag::Bag out(edited.string(), rosbag::bagmode::Write);
  for (const auto& m : rosbag::View(in)) {
    auto corrections = m.instantiate<ppp_bayes_tree::PreciseCorrections>();
    if (!corrections) {
      out.write(m.getTopic(), m.getTime(), m, m.getConnectionHeader());
      continue;
    }
    ppp_bayes_tree::PreciseCorrections copy = *corrections;
    if (edit(copy)) out.write(m.getTopic(), m.getTime(), copy);
  }
}

TEST_F(BagSolve, CorrectionsEndingEarlyAreNamedAndCorrectionsOfAnotherTimeRefused) {
  const fs::path original = dir_ / "bags" / "flight_a.bag";
  const std::string args = " --config " + kConfigs + " --name sim --no-timings --out ";
  double first_s = -1.0;
  const fs::path early = dir_ / "early.bag", other_week = dir_ / "other_week.bag";
  writeEditedCorrections(original, early, [&](ppp_bayes_tree::PreciseCorrections& c) {
    if (first_s < 0) first_s = c.seconds_of_week;
    return c.seconds_of_week <= first_s + 120.0;  // the first two of the three minutes
  });
  writeEditedCorrections(original, other_week, [](ppp_bayes_tree::PreciseCorrections& c) {
    c.week += 1;
    return true;
  });
  const fs::path out_file = dir_ / "coverage_stdout.txt";
  const std::string early_solve =
      kBin + "/ppp_bag_solve " + early.string() + args + (dir_ / "early_out").string() + " > " + out_file.string() + " 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(early_solve.c_str())), 0) << readText(out_file);
  const std::string report = readText(out_file);
  EXPECT_NE(report.find("coverage: corrections (early.bag) end at "), std::string::npos) << report;
  EXPECT_NE(report.find(": epochs after are not solved"), std::string::npos) << report;

  std::string err;
  EXPECT_EQ(bagSolve(other_week.string() + args + (dir_ / "other_week_out").string(), dir_ / "week.txt", err), 1)
      << err;
  EXPECT_NE(err.find("products do not cover the observations: corrections (other_week.bag) span "), std::string::npos)
      << err;
  EXPECT_EQ(err.find("no clock"), std::string::npos) << err;
}

TEST_F(BagSolve, CampaignOfTwoBagJobsRunsResumesAndSummarises) {
  const fs::path manifest = dir_ / "bags.yaml", out = dir_ / "campaign";
  std::ofstream(manifest) << "campaign: {name: flights, data_root: .}\n"
                          << "bags:\n  - name: flight\n    bag: \"bags/*.bag\"\n    config: [" << kRepo
                          << "/config/ppp.yaml, " << kRepo << "/config/ppp_simulated.yaml]\n";
  const std::string campaign = kBin + "/ppp_campaign run " + manifest.string() + " --out " + out.string() +
                               " --jobs 2 --no-plot";
  ASSERT_EQ(run(campaign), 0) << campaign;
  const auto rows = readCsv(out / "summary.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& r : rows) {
    EXPECT_EQ(r.at("kind"), "bag");
    EXPECT_EQ(r.at("state"), "done") << r.at("id") << ": " << r.at("reason");
    EXPECT_EQ(r.at("epochs_read"), "181");
    ASSERT_FALSE(r.at("mean_3d_cm").empty()) << "the truth from the bag's truth/path";
  }
  // The job's figures are those of ppp_bag_solve run by hand on its bag.
  const fs::path direct = dir_ / "direct";
  ASSERT_EQ(run(kBin + "/ppp_bag_solve " + (dir_ / "bags" / "flight_a.bag").string() + " --config " + kConfigs +
                " --name flight --no-timings --out " + direct.string()),
            0);
  char expected[32];
  std::snprintf(expected, sizeof expected, "%.2f",
                allEpochsFigure(readText(direct / "flight_ekf_summary.json"), "mean_m") * 100.0);
  EXPECT_EQ(rows[0].at("mean_3d_cm"), expected);
  EXPECT_EQ(readText(direct / "flight_ekf.csv"), readText(out / "jobs" / rows[0].at("id") / "output" / "flight_ekf.csv"));
  EXPECT_EQ(rows[0].at("id"), "flight_flight_a");
  EXPECT_EQ(rows[1].at("id"), "flight_flight_b");
  for (const auto& r : rows)
    EXPECT_TRUE(fs::exists(out / "jobs" / r.at("id") / "output" / "flight_ekf.csv")) << r.at("id");

  // Resume: a finished job is not run again; a job without its marker is.
  const fs::path done_a = out / "jobs" / "flight_flight_a" / "done.json";
  const fs::path done_b = out / "jobs" / "flight_flight_b" / "done.json";
  const auto time_a = fs::last_write_time(done_a);
  fs::remove(done_b);
  fs::remove_all(out / "jobs" / "flight_flight_b" / "output");
  fs::create_directories(out / "jobs" / "flight_flight_b" / "work");  // as a killed attempt leaves it
  ASSERT_EQ(run(campaign), 0) << campaign;
  EXPECT_EQ(fs::last_write_time(done_a), time_a) << "the finished job ran again";
  ASSERT_TRUE(fs::exists(done_b));
  const auto again = readCsv(out / "summary.csv");
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[1].at("state"), "done");
  EXPECT_EQ(again[1].at("mean_3d_cm"), rows[1].at("mean_3d_cm")) << "the same figures after the re-run";

  // A missing bag is named before anything runs.
  std::ofstream(manifest, std::ios::app) << "  - name: lost\n    bag: bags/lost.bag\n";
  const std::string check = kBin + "/ppp_campaign check " + manifest.string() + " > " + (dir_ / "check.txt").string() +
                            " 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(check.c_str())), 2);
  EXPECT_NE(readText(dir_ / "check.txt").find("bags/lost.bag: no such file"), std::string::npos)
      << readText(dir_ / "check.txt");
}

}  // namespace
