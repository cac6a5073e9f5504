// ppp_to_bag: an archive dataset or a simulated flight as a replay bag.
//
//   ppp_to_bag --obs OBS.rnx --sp3 F [F...] --clk F [F...] [--bia F] [--interval 30]
//              [--max-epochs N] --out X.bag
//   ppp_to_bag --simulate loiter|survey|figure8|climb [--duration-min N] [--rate 1|10]
//              [--seed S] [--config simulation.yaml] [--truth-out TRUTH.csv] --out X.bag
//   ppp_to_bag --ubx REC.ubx [--ubx-topic gnss/receiver] --out X.bag
// --ubx: a u-blox UBX recording as a bag of the live input instead (ros.live; the
// broadcast ephemerides come from its RXM-SFRBX): each UBX frame, unchanged, as one
// ppp_bayes_tree/GnssStreamBytes (format "ubx") on --ubx-topic, stamped at the receiver
// time of the newest RXM-RAWX epoch (ros/bag_writer.h, writeUbxBag).
// Writes gnss/observations (one GnssObservations per epoch) and gnss/corrections
// (one PreciseCorrections per product epoch, every --interval s: orbits
// interpolated from the SP3, clocks from the CLK records), stamped in UTC.
// A simulated flight also gets its truth: truth/path (nav_msgs/Path of the true
// antenna positions in the earth frame = ECEF, latched, at the first epoch, so
// RViz shows it beside the estimates through earth -> map), and with
// --truth-out the truth CSV of the simulator (writeTruthEpochsCsv: time_gpst,
// gps_week, seconds_of_week, x_m, y_m, z_m, ...), which ppp_bag_report reads.
// ANTEX/BLQ files are not carried by the bag: the node reads them (ros.products).
// Satellite biases for integer ambiguity resolution (--ar-biases auto, the
// default): the batches carry, per satellite and observed signal, the code and
// phase OSBs that make the ambiguities integer with the batch's clocks
// (PreciseCorrections ar_bias_source, satellites[].biases): the --bia file's
// phase OSBs when they come from the clocks' analysis centre, else the wide-lane
// biases of integer-recovery clocks (GRG) from the clock header; none otherwise
// (said on the output). --ar-biases none leaves them out.
// IMU (either form): --imu FILE adds its readings on imu/data (sensor_msgs/Imu in
// --imu-frame, default imu_link; ros/imu_conversions.h): a plain IMU CSV
// (doc/gnss_ins.md, "IMU files"), or with --imu-tag TAG an IMU logged beside the
// receiver by RTKLIB with its time-tag file. The readings pass the IMU input
// screen (navigation/imu_input_screen.h) first: what it refuses is said, with
// the reader's own problems, and a stream with no reading left is an error.
#include <fstream>
#include <iterator>
#include <iostream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/imu/imu_file_loader.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/products/product_antenna_model.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/ros/bag_writer.h"
#include "ppp_bayes_tree/ros/message_conversions.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/simulation_writers.h"

namespace {

int usage(const std::string& why) {
  std::cerr << "ppp_to_bag: " << why << "\n"
            << "usage: ppp_to_bag --obs OBS --sp3 F [F...] --clk F [F...] [--bia F] [--interval S] [--max-epochs N]\n"
            << "                  [--ar-biases auto|none] --out BAG\n"
            << "       ppp_to_bag --simulate PROFILE [--duration-min N] [--rate 1|10] [--seed S] [--config YAML]\n"
            << "                  [--truth-out TRUTH.csv] --out BAG\n"
            << "       ppp_to_bag --ubx REC.ubx [--ubx-topic TOPIC] --out BAG\n"
            << "       any form: [--imu FILE [--imu-tag TAG] [--imu-frame FRAME]]\n";
  return 2;
}

/// The product assembly of the files with ambiguity resolution on: its PPP-AR gate
/// picks the phase information (see the top comment).
ppp::ProductAssembly assembleForBiases(const std::vector<std::string>& sp3, const std::vector<std::string>& clk,
                                       const std::string& bia) {
  ppp::ProductAssemblyInputs in;
  in.sp3 = sp3;
  in.clk = clk;
  if (!bia.empty()) in.bias = bia;
  ppp::PppConfig config;
  config.ambiguity_resolution.enabled = true;
  return ppp::ProductAssembly::assemble(in, config);
}

/// The readings of an IMU file through the input screen (io/imu/imu_file_loader.h);
/// the reader's problems and the screen's refusals are said on stderr. Throws when
/// none is left.
std::vector<ppp::ImuSample> screenedImu(const std::string& path, const std::string& tag) {
  ppp::ImuFileOptions file;
  file.path = path;
  file.tag_path = tag;
  file.format = tag.empty() ? ppp::ImuFileFormat::PlainCsv : ppp::ImuFileFormat::RtklibLogged;
  ppp::ImuFileLoad load = ppp::loadImuFile(file);
  std::cout << "ppp_to_bag: " << path << ": " << load.screen_summary << "\n";
  for (const std::string& line : load.problemLines()) std::cerr << "ppp_to_bag: " << line << "\n";
  if (load.samples.empty()) throw std::runtime_error(path + ": no IMU reading left after the input screen");
  return std::move(load.samples);
}

/// The --ubx form: the recording's frames on the stream topic (and the IMU, when given).
ppp_ros::BagWriteSummary writeUbxRecording(const std::string& ubx, const std::string& out,
                                           const ppp_ros::UbxBagOptions& ubx_options,
                                           const ppp_ros::BagWriteOptions& options) {
  std::ifstream in(ubx, std::ios::binary);
  if (!in) throw std::runtime_error(ubx + ": cannot open the UBX recording");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const ppp_ros::BagWriteSummary s = ppp_ros::writeUbxBag(out, bytes, ubx_options, options);
  std::cout << "ppp_to_bag: " << ubx << ": " << s.frames << " UBX frames on " << ubx_options.ubx_topic << " ("
            << s.epochs << " RXM-RAWX epochs)\n";
  if (!s.stream_problems.empty()) std::cerr << "ppp_to_bag: " << ubx << ": framing problems:\n" << s.stream_problems;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string obs, bia, out, profile, sim_config, truth_out, ar_biases = "auto", imu, imu_tag, ubx;
  ppp_ros::UbxBagOptions ubx_options;
  std::vector<std::string> sp3, clk;
  ppp_ros::BagWriteOptions options;
  double duration_min = 10.0, rate = 1.0;
  unsigned long long seed = 1;
  std::vector<std::string>* list = nullptr;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) {
      if (!list) return usage("unexpected argument " + a);
      list->push_back(a);
      continue;
    }
    list = nullptr;
    if (a == "--sp3") { list = &sp3; continue; }
    if (a == "--clk") { list = &clk; continue; }
    if (i + 1 >= argc) return usage("missing value after " + a);
    const std::string v = argv[++i];
    try {
      if (a == "--obs") obs = v;
      else if (a == "--bia") bia = v;
      else if (a == "--out") out = v;
      else if (a == "--simulate") profile = v;
      else if (a == "--config") sim_config = v;
      else if (a == "--truth-out") truth_out = v;
      else if (a == "--ar-biases") ar_biases = v;
      else if (a == "--imu") imu = v;
      else if (a == "--imu-tag") imu_tag = v;
      else if (a == "--imu-frame") options.imu_frame = v;
      else if (a == "--ubx") ubx = v;
      else if (a == "--ubx-topic") ubx_options.ubx_topic = v;
      else if (a == "--interval") options.correction_interval_s = std::stod(v);
      else if (a == "--max-epochs") options.max_epochs = std::stoul(v);
      else if (a == "--duration-min") duration_min = std::stod(v);
      else if (a == "--rate") rate = std::stod(v);
      else if (a == "--seed") seed = std::stoull(v);
      else return usage("unknown option " + a);
    } catch (const std::exception&) {
      return usage("bad value for " + a + ": " + v);
    }
  }
  if (out.empty()) return usage("--out BAG is required");
  if (ar_biases != "auto" && ar_biases != "none") return usage("--ar-biases must be auto or none, not " + ar_biases);
  if (!(options.correction_interval_s >= 1.0)) return usage("--interval must be >= 1 s");
  if (!truth_out.empty() && profile.empty()) return usage("--truth-out needs --simulate (real data: give the truth to ppp_bag_report)");
  if (!imu_tag.empty() && imu.empty()) return usage("--imu-tag needs --imu");
  if (!ubx.empty() && (!profile.empty() || !obs.empty()))
    return usage("--ubx is a form of its own: not with --obs or --simulate");
  try {
    if (!imu.empty()) options.imu = screenedImu(imu, imu_tag);
    ppp_ros::BagWriteSummary s;
    if (!ubx.empty()) {
      s = writeUbxRecording(ubx, out, ubx_options, options);
    } else if (!profile.empty()) {
      ppp::SimulationConfig config;
      if (!sim_config.empty()) config = ppp::loadSimulationConfig(sim_config);
      config.profile = ppp::parseFlightProfile(profile);
      config.duration_s = duration_min * 60.0;
      config.rate_hz = rate;
      const ppp::SimulatedFlight f = ppp::simulateFlight(config, seed);
      s = ppp_ros::writeSimulatedFlightBag(out, f, options, "/ppp_to_bag");
      if (!truth_out.empty()) {
        std::ofstream csv(truth_out);
        ppp::writeTruthEpochsCsv(csv, f);
        csv.close();
        if (!csv) throw std::runtime_error("cannot write the truth CSV " + truth_out);
        std::cout << "ppp_to_bag: truth of " << f.truth.size() << " epochs -> " << truth_out << "\n";
      }
    } else {
      if (obs.empty() || sp3.empty() || clk.empty()) return usage("give --obs, --sp3 and --clk (or --simulate)");
      const ppp::PreciseEphemeris products = ppp::PreciseEphemeris::load(sp3, clk);
      auto reader = ppp::RinexObsReader::open(obs);
      options.orbit_source = ppp::fileBaseName(sp3.front()) + " (Lagrange-interpolated)";
      options.clock_source = ppp::fileBaseName(clk.front());
      options.reference_frame = "IGS20";
      options.bias_set = bia.empty() ? "" : ppp::fileBaseName(bia);
      try {
        options.antenna_model = ppp::productAntennaModel(clk.front());
      } catch (const std::exception&) {  // no model named: the bag says "not known"
      }
      std::optional<ppp::ProductAssembly> assembly;
      if (ar_biases == "auto") {
        assembly = assembleForBiases(sp3, clk, bia);
        options.ar_biases = assembly->phaseBiases();
        options.ar_bias_kind = ppp_ros::arBiasKind(assembly->arGate().phase);
        std::cout << "ppp_to_bag: biases for ambiguity resolution: "
                  << (options.ar_biases ? options.ar_biases->describeSource() : "none: " + assembly->arGate().text())
                  << "\n";
      }
      s = ppp_ros::writeReplayBag(out, reader.header(), [&](ppp::ObsEpoch& e) { return reader.next(e); }, products,
                                  options);
    }
    std::cout << "ppp_to_bag: " << out << ": " << s.epochs << " observation epochs";
    if (s.first) std::cout << " (" << s.first->toString() << " .. " << s.last->toString() << ")";
    if (ubx.empty()) std::cout << ", " << s.batches << " correction batches every " << options.correction_interval_s << " s";
    if (s.imu_readings > 0) std::cout << ", " << s.imu_readings << " IMU readings on " << options.imu_topic;
    std::cout << "\n";
  } catch (const std::exception& e) {
    std::cerr << "ppp_to_bag: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
