// ppp_simulate: simulates one UAV flight and writes its GPS L1/L2
// RINEX 3.04 observations, the "precise products" (truth + product error,
// SP3-c and RINEX clock), the truth products and the truth CSV files.
//
// usage: ppp_simulate --profile loiter|survey|figure8|climb [--trajectory CSV]
//                     [--rate 1|10] [--duration-min N] [--seed S]
//                     [--sp3 F --clk F] [--config YAML] [--out DIR] [--bag BAG]
//                     [--imu consumer_mems|industrial_mems|tactical]
// --imu adds the readings of an IMU of that grade (imu.csv, imu_bias.csv; the same
// as the YAML's imu: { enabled: true, grade: ... }).
// --out writes the files; --bag writes the flight as a replay bag (gnss/observations,
// gnss/corrections from the products with error, truth/path), the same as
// `ppp_to_bag --simulate` but with every simulator input (trajectory, products);
// --bag needs the catkin build (PPP_WITH_ROSBAG), the plain-CMake core build
// refuses it with a message. At least one of --out and --bag.
// The CSV trajectory layout is documented in simulation/flight_trajectory.h,
// the YAML keys in simulation/simulation_config.h. Command-line values override
// the YAML. Same seed and inputs -> identical files, byte for byte.
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/config/yaml_section.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/simulation/simulation_writers.h"
#ifdef PPP_WITH_ROSBAG
#include "ppp_bayes_tree/ros/bag_writer.h"
#endif

namespace {

int usage(const std::string& why) {
  std::cerr << "ppp_simulate: " << why << "\n"
            << "usage: ppp_simulate --profile loiter|survey|figure8|climb [--trajectory CSV]\n"
            << "                    [--rate 1|10] [--duration-min N] [--seed S]\n"
            << "                    [--sp3 F --clk F] [--config YAML] [--out DIR] [--bag BAG]\n"
            << "                    [--imu consumer_mems|industrial_mems|tactical]\n";
  return 2;
}

bool parseNumber(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end != s.c_str() && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  std::string profile = "loiter", trajectory, sp3, clk, config_path, out, bag, imu_grade;
  std::optional<double> rate, duration_min;
  std::uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage("missing value after " + a);
    const std::string v = argv[++i];
    double x = 0.0;
    if (a == "--profile") profile = v;
    else if (a == "--trajectory") trajectory = v;
    else if (a == "--sp3") sp3 = v;
    else if (a == "--clk") clk = v;
    else if (a == "--config") config_path = v;
    else if (a == "--out") out = v;
    else if (a == "--bag") bag = v;
    else if (a == "--imu") imu_grade = v;
    else if (a == "--rate") {
      if (!parseNumber(v, x) || (x != 1.0 && x != 10.0)) return usage("--rate must be 1 or 10");
      rate = x;
    } else if (a == "--duration-min") {
      if (!parseNumber(v, x) || !(x > 0.0) || x > 1440.0) return usage("--duration-min must be in (0, 1440]");
      duration_min = x;
    } else if (a == "--seed") {
      char* end = nullptr;
      seed = std::strtoull(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || v[0] == '-') return usage("--seed must be a non-negative integer");
    } else {
      return usage("unknown option " + a);
    }
  }
  if (out.empty() && bag.empty()) return usage("give --out DIR, --bag BAG or both");
#ifndef PPP_WITH_ROSBAG
  if (!bag.empty())
    return usage("--bag needs the catkin build (this ppp_simulate is the plain-CMake core build without rosbag)");
#endif
  if (sp3.empty() != clk.empty()) return usage("give --sp3 and --clk together");
  try {
    ppp::SimulationConfig config;
    if (!config_path.empty()) config = ppp::loadSimulationConfig(config_path);
    config.profile = ppp::parseFlightProfile(profile);
    if (rate) config.rate_hz = *rate;
    if (duration_min) config.duration_s = *duration_min * 60.0;
    if (!imu_grade.empty())
      config = ppp::parseSimulationConfig("imu: { enabled: true, grade: " + imu_grade + " }", "--imu", config);
    ppp::SimulationSources sources;
    if (!sp3.empty()) {
      sources.sp3 = ppp::readSp3(sp3);
      sources.clk = ppp::readRinexClock(clk);
    }
    if (!trajectory.empty()) {
      const ppp::GnssTime start =
          config.start ? *config.start : ppp::GnssTime::fromCalendar({2026, 5, 13, 10, 0, 0.0}, ppp::TimeSystem::GPS);
      sources.trajectory = ppp::readTrajectoryCsv(trajectory, start);
    }
    const ppp::SimulatedFlight flight = ppp::simulateFlight(config, seed, sources);
    std::vector<std::string> written;
    if (!out.empty()) written = ppp::writeSimulatedFlight(flight, out);
#ifdef PPP_WITH_ROSBAG
    if (!bag.empty()) {
      const auto s = ppp_ros::writeSimulatedFlightBag(bag, flight, {}, "/ppp_simulate");
      written.push_back(bag + " (" + std::to_string(s.epochs) + " observation epochs, " +
                        std::to_string(s.batches) + " correction batches, truth/path)");
    }
#endif
    std::cout << "ppp_simulate: " << (trajectory.empty() ? "profile " + profile : "trajectory " + trajectory)
              << ", seed " << seed << ", " << flight.epochs.size() << " epochs at " << config.rate_hz << " Hz ("
              << flight.truth.front().trajectory.time.toString(ppp::TimeSystem::GPS, 0) << " .. "
              << flight.truth.back().trajectory.time.toString(ppp::TimeSystem::GPS, 0) << ")\n";
    std::cout << "constellation: " << (sp3.empty() ? "nominal Walker" : "products " + sp3 + " / " + clk) << ", "
              << flight.truth_products.orbitSatellites().size() << " GPS satellites\n";
    std::cout << "drawn parameters:\n";
    for (const auto& l : flight.drawn.describe()) std::cout << "  " << l << "\n";
    double max_roll = 0.0;
    for (const auto& t : flight.truth) max_roll = std::max(max_roll, std::abs(t.trajectory.roll_rad));
    std::cout << "arcs " << flight.arcs.size() << ", injected phase breaks " << flight.breaks.size()
              << ", max |roll| " << max_roll * ppp::kRadToDeg << " deg\n";
    if (!flight.imu.samples.empty())
      std::cout << "IMU: " << flight.imu.noise.name << ", " << flight.imu.samples.size() << " readings at "
                << config.imu.rate_hz << " Hz" << (config.imu.errors ? "" : " (true readings, no errors)") << "\n";
    std::cout << "wrote:\n";
    for (const auto& p : written) std::cout << "  " << p << "\n";
  } catch (const std::exception& e) {  // ParseError, FileOpenError, ConfigError (name the file) and the rest
    std::cerr << "ppp_simulate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
