// ppp_solve: offline kinematic PPP of one RINEX observation file with precise
// products (the pipeline of ppp/pipeline/ppp_pipeline.h; outputs of app/ppp_solve_run.h).
//
// usage: ppp_solve (--obs F | --rtcm F [--ref-date YYYY/MM/DD] | --ubx F)
//                  (--sp3 F... --clk F... | --nav F... [--ssr F [--ssr-reference com|apc|apc-l1]])
//                  --atx F... [--bia F] [--blq F]
//                  [--config YAML...] [--estimator ekf|smoother|ekf_ins|smoother_ins|both] [--truth X,Y,Z] [--name N] --out DIR
// (the estimators: ppp/estimators/estimator_registry.h; --help lists them)
//                  [--no-product-checks] [--start "YYYY/MM/DD HH:MM:SS"] [--end "YYYY/MM/DD HH:MM:SS"]
//                  [--gnss-gap "YYYY/MM/DD HH:MM:SS,SECONDS"]
//                  [--imu F [--imu-format csv|logged] [--imu-tag F] [--imu-grade consumer|industrial|tactical]
//                   [--lever-arm X,Y,Z] [--imu-rotation R,P,Y]
//                   [--imu-attitude R,P,H | --imu-heading DEG | --heading-speed M/S]
//                   [--doppler on|off] [--doppler-sigma M/S] [--noise-adaptation on|off]
//                   [--gap-bridge-max-s S]]
// --doppler: ekf_ins's velocity update from the Doppler of the observations
// (default on; ppp/estimators/ppp_ins_ekf.h), --doppler-sigma its range-rate
// sigma at the zenith [m/s, default 0.05], divided by sin(elevation).
// --noise-adaptation: the GNSS/INS estimators scale the accelerometers' process noise
// of a prediction the carrier phases find inconsistent (default on;
// ppp/estimators/ins_process_noise_adaptation.h).
// --gap-bridge-max-s: GNSS gaps up to this long [s, 0-600, default 90] do not end the
// GNSS/INS estimators' arcs: the gap bridge tests them against the INS prediction
// (InsEkfOptions::gap_bridge_max_s); 0: every longer gap than the arc tracker's ends them.
// --imu: the IMU readings of the GNSS/INS estimators (--estimator ekf_ins or
// smoother_ins, which need them; the other estimators ignore them): the plain CSV
// (default, doc/gnss_ins.md) or a logged IMU CSV with its RTKLIB time-tag file
// (--imu-format logged --imu-tag F), read and screened by io/imu/imu_file_loader.h
// (no reading left: exit status 1).
// --imu-grade: the IMU's noise preset (default industrial); --lever-arm: antenna
// minus IMU in the body frame [m] (default 0,0,0); --imu-heading: the heading of
// the body x axis at the start [deg from north, clockwise]; roll and pitch come from
// levelling the readings up to the first epoch (the platform at rest). Without
// --imu-heading the heading is aligned in motion (ppp/estimators/ins_in_motion_alignment.h):
// roll and pitch from the latest static interval before the start, the heading
// from the course over ground once the antenna moves faster than --heading-speed
// [m/s, default 0.5] (the body x axis taken as the direction of motion). ekf_ins
// writes the EKF's files under <name>_ekf_ins* and <name>_ekf_ins_attitude.csv
// (attitude and velocity after each epoch; doc/gnss_ins.md); smoother_ins writes the
// smoother's files under <name>_smoother_ins_{filtered,smoothed}* and
// <name>_smoother_ins_attitude.csv. smoother_ins aligns in motion with ekf_ins's rule
// (ppp/estimators/ins_in_motion_alignment.h): GNSS-only until the course gives the
// heading, its NavState (and attitude file rows) from the next solved epoch on.
// --imu-attitude: the whole start attitude of the body, roll, pitch and heading
// [deg] in the local north-east-down frame (R_ned_body = Rz(heading) Ry(pitch)
// Rx(roll)), for a start in motion where levelling cannot work (the nodes'
// ros.imu.initial_attitude given); not with --imu-heading.
// --imu-rotation: the IMU's mounting, its axes rotated from the body's by roll,
// pitch, yaw [deg] (R_body_imu = Rz(yaw) Ry(pitch) Rx(roll)); the readings are
// turned into the body axes (io/imu/imu_file_loader.h) before the filter sees them.
// --gnss-gap: a GNSS outage of SECONDS from the GPST start: those epochs are kept
// without any satellite (an inertial estimator coasts through them; the others
// have no solution there).
// --start/--end (GPST): only the epochs in [start, end) are processed (e.g. one
// hour of a day file; io/rinex/time_window_source.h); either may be given alone.
// Several --config files are laid one on another in order, as the nodes load
// config/ppp.yaml and its overrides (ppp_config.h: mappings merge, a later value wins).
// --no-product-checks skips the SP3/CLK sanity checks (product_sanity.h), only to
// measure what the estimators' own postfit and consistency tests catch.
// Several files may follow --sp3, --clk, --nav, --atx and --config (or the option may be repeated).
// A --nav file may be RINEX navigation or an RTCM 3 / UBX recording (detected by
// content): its ephemerides are used from their reception in the stream on, so
// `--rtcm X --nav X` is broadcast-only PPP from one recording.
// ANTEX files are searched in the order given: the first holding an antenna wins,
// except that a satellite's antenna comes first from the family the products name
// (IGS14, IGS20: so igs14.atx and igs20.atx may be given together, in any order).
// The products decide the defaults (ppp/pipeline/product_assembly.h, printed in the notes):
// the systems (every one of GPS | GLONASS | Galileo the products and antennas cover) and
// PPP-AR (ambiguity_resolution.enabled: auto fixes only with phase information
// consistent with the clocks and the products' satellite antenna model).
// ekf writes DIR/<name>_ekf.csv, .pos (RTKLIB), _summary.json, _epochs.csv and
// _residuals.csv; smoother writes the FILTERED and the SMOOTHED solutions as
// <name>_smoother_filtered.* and <name>_smoother_smoothed.* (csv, pos, summary.json),
// plus <name>_smoother_epochs.csv, _residuals.csv and _biases.csv, and prints the
// per-epoch update time median and p99; both runs the EKF and the smoother (one
// pipeline run each) and prints one table EKF | smoother filtered | smoother smoothed.
// Prints the statistics (with --truth) and the notes (see app/ppp_solve_run.h).
// Exit status: 0 solved; 3 solved, but the inputs had problems (a truncated or
// broken product file, single bad product values, malformed or refused epochs:
// listed under "problems", with the satellites the run never used); 1 nothing
// solved or an error (the file and line named); 2 usage.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ppp_bayes_tree/app/ppp_solve_run.h"
#include "ppp_bayes_tree/io/imu/imu_file_loader.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"
#include "ppp_bayes_tree/navigation/ins_alignment.h"
#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"
#include "ppp_bayes_tree/ppp/pipeline/product_sources.h"

namespace {

int usage(const std::string& why) {
  std::cerr << "ppp_solve: " << why << "\n"
            << "usage: ppp_solve (--obs F | --rtcm F [--ref-date YYYY/MM/DD] | --ubx F)\n"
            << "                 (--sp3 F... --clk F... | --nav F... [--ssr F [--ssr-reference com|apc|apc-l1]])\n"
            << "                 --atx F... [--bia F] [--blq F]\n"
            << "                 [--config YAML...] [--estimator " << ppp::registeredEstimatorNames("|") << '|'
            << ppp::kAllEstimators << "] [--truth X,Y,Z] [--name N] --out DIR\n"
            << "                 [--no-product-checks] [--start \"YYYY/MM/DD HH:MM:SS\"] [--end \"YYYY/MM/DD HH:MM:SS\"]\n"
            << "                 [--gnss-gap \"YYYY/MM/DD HH:MM:SS,SECONDS\"]\n"
            << "                 [--imu F [--imu-format csv|logged] [--imu-tag F] [--imu-grade consumer|industrial|tactical]\n"
            << "                  [--lever-arm X,Y,Z] [--imu-rotation R,P,Y]\n"
            << "                  [--imu-attitude R,P,H | --imu-heading DEG | --heading-speed M/S]\n"
            << "                  [--doppler on|off] [--doppler-sigma M/S] [--noise-adaptation on|off]\n"
            << "                  [--gap-bridge-max-s S]]\n"
            << "                  (ekf_ins, smoother_ins need --imu)\n"
            << "estimators (--estimator; default " << ppp::kDefaultEstimator << ", "
            << ppp::kAllEstimators << ": each in turn):\n";
  for (const ppp::EstimatorEntry& e : ppp::kEstimators) std::cerr << "  " << e.name << ": " << e.description << "\n";
  std::cerr << "orbit and clock sources (by the files given):\n";
  for (const ppp::ProductSource& s : ppp::kProductSources)
    if (!s.streamed) std::cerr << "  " << s.name << ": " << s.description << "\n";
  return 2;
}

bool parseTruth(const std::string& s, Eigen::Vector3d& t) {
  std::stringstream ss(s);
  std::string item;
  int k = 0;
  while (std::getline(ss, item, ',')) {
    if (k == 3) return false;
    char* end = nullptr;
    t(k++) = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0') return false;
  }
  return k == 3;
}

/// The IMU options of the GNSS/INS filter.
struct ImuArgs {
  ppp::ImuFileOptions file;
  ppp::InsEkfOptions ins;
};

/// Parses one IMU option at argv[i] (moving i past its value): nullopt when `a` is
/// none of them, "" when parsed, else the usage error.
std::optional<std::string> parseImuOption(const std::string& a, int argc, char** argv, int& i, ImuArgs& imu) {
  const bool has_value = i + 1 < argc;
  const std::string v = has_value ? argv[i + 1] : "";
  if (a != "--imu" && a != "--imu-format" && a != "--imu-tag" && a != "--imu-grade" && a != "--lever-arm" &&
      a != "--imu-heading" && a != "--heading-speed" && a != "--imu-rotation" && a != "--imu-attitude")
    return std::nullopt;
  if (!has_value) return a + " needs a value";
  ++i;
  if (a == "--imu") imu.file.path = v;
  else if (a == "--imu-tag") imu.file.tag_path = v;
  else if (a == "--imu-format") {
    if (v != "csv" && v != "logged") return std::string("--imu-format needs csv or logged");
    imu.file.format = v == "logged" ? ppp::ImuFileFormat::RtklibLogged : ppp::ImuFileFormat::PlainCsv;
  } else if (a == "--imu-grade") {
    const std::optional<ppp::ImuGrade> grade = ppp::imuGradeFromName(v);
    if (!grade) return std::string("--imu-grade needs consumer, industrial or tactical");
    imu.ins.noise = ppp::imuNoisePreset(*grade);
  } else if (a == "--lever-arm") {
    if (!parseTruth(v, imu.ins.lever_arm_body_m)) return std::string("--lever-arm needs X,Y,Z in metres (body frame)");
  } else if (a == "--imu-rotation") {
    Eigen::Vector3d deg;
    if (!parseTruth(v, deg) || !deg.allFinite())
      return std::string("--imu-rotation needs ROLL,PITCH,YAW in degrees (the IMU's axes from the body's)");
    imu.file.rotation_body_imu = ppp::rotationNedBody(deg.x() * M_PI / 180.0, deg.y() * M_PI / 180.0,
                                                      deg.z() * M_PI / 180.0);
  } else if (a == "--imu-attitude") {
    Eigen::Vector3d deg;
    if (!parseTruth(v, deg) || !deg.allFinite())
      return std::string("--imu-attitude needs ROLL,PITCH,HEADING in degrees (the body in north-east-down)");
    imu.ins.initial_rotation_ned_body = ppp::rotationNedBody(deg.x() * M_PI / 180.0, deg.y() * M_PI / 180.0,
                                                             deg.z() * M_PI / 180.0);
  } else if (a == "--heading-speed") {
    char* end = nullptr;
    const double speed = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0' || !(speed > 0.0) || !std::isfinite(speed))
      return std::string("--heading-speed needs a speed > 0 in m/s");
    imu.ins.heading_alignment.min_horizontal_speed_mps = speed;
  } else {
    char* end = nullptr;
    const double deg = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0' || !std::isfinite(deg)) return std::string("--imu-heading needs degrees");
    imu.ins.initial_heading_rad = deg * M_PI / 180.0;
  }
  return std::string();
}

/// Parses --doppler on|off and --doppler-sigma M/S (ekf_ins's Doppler velocity
/// update, InsEkfOptions::doppler), --noise-adaptation on|off
/// (InsEkfOptions::process_noise_adaptation) and --gap-bridge-max-s S
/// (InsEkfOptions::gap_bridge_max_s): nullopt when `a` is none of them, "" when
/// parsed, else the usage error.
std::optional<std::string> parseDopplerOption(const std::string& a, int argc, char** argv, int& i, ImuArgs& imu) {
  if (a != "--doppler" && a != "--doppler-sigma" && a != "--noise-adaptation" && a != "--gap-bridge-max-s")
    return std::nullopt;
  if (i + 1 >= argc) return a + " needs a value";
  const std::string v = argv[++i];
  if (a == "--gap-bridge-max-s") {
    char* end = nullptr;
    const double s = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0' || !(s >= 0.0) || !(s <= 600.0))
      return std::string("--gap-bridge-max-s needs seconds in [0, 600]");
    imu.ins.gap_bridge_max_s = s;
    return std::string();
  }
  if (a == "--doppler" || a == "--noise-adaptation") {
    if (v != "on" && v != "off") return a + " needs on or off";
    (a == "--doppler" ? imu.ins.doppler.enabled : imu.ins.process_noise_adaptation.enabled) = v == "on";
    return std::string();
  }
  char* end = nullptr;
  const double sigma = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || *end != '\0' || !(sigma > 0.0) || !std::isfinite(sigma))
    return std::string("--doppler-sigma needs a range-rate sigma > 0 in m/s");
  imu.ins.doppler.sigma_zenith_mps = sigma;
  return std::string();
}

/// What is wrong with the IMU options for `estimator`; empty when nothing.
std::string imuUsageProblem(const std::string& estimator, const ImuArgs& imu) {
  const ppp::EstimatorEntry* chosen = ppp::findEstimator(estimator);
  if (chosen && chosen->state == ppp::EstimatedState::GnssInertial && imu.file.path.empty())
    return "--estimator " + estimator + " needs IMU readings: --imu FILE";
  if (imu.file.format == ppp::ImuFileFormat::RtklibLogged && imu.file.tag_path.empty())
    return "--imu-format logged needs --imu-tag (the time-tag file)";
  if (imu.ins.initial_rotation_ned_body && imu.ins.initial_heading_rad)
    return "--imu-attitude and --imu-heading are two starts: give one";
  return {};
}

/// The screened readings of --imu (io/imu/imu_file_loader.h); the reader's and the
/// screen's problems on stderr. Throws when no reading is left.
std::vector<ppp::ImuSample> readImu(const ImuArgs& imu) {
  ppp::ImuFileLoad load = ppp::loadImuFile(imu.file);
  std::cerr << "ppp_solve: IMU file " << imu.file.path << ": " << load.screen_summary << "\n";
  for (const std::string& line : load.problemLines()) std::cerr << "ppp_solve: IMU file " << line << "\n";
  if (load.samples.empty())
    throw std::runtime_error("IMU file " + imu.file.path + ": no reading left after the input screen");
  return std::move(load.samples);
}

/// Progress bar on stderr (only when stderr is a terminal).
void drawProgress(double fraction, const ppp::PppEpochRecord& rec) {
  const int width = 30;
  const int filled = static_cast<int>(fraction * width + 0.5);
  std::fprintf(stderr, "\r[%-*s] %3.0f%%  %s  %2zu sats  ", width, std::string(filled, '#').c_str(), fraction * 100,
               rec.solution.time.toString().c_str(), rec.used.size());
  std::fflush(stderr);
}

/// Everything the command line gives.
struct SolveArgs {
  ppp::PppSolveRequest req;
  std::vector<std::string> config_paths;
  ImuArgs imu;
};

/// Parses the observation, product and output options at argv[i] (moving i past
/// its value): "" when parsed, else the usage error. `value` takes the next argument.
std::string parseOption(const std::string& a, int argc, char** argv, int& i, SolveArgs& args) {
  ppp::PppSolveRequest& req = args.req;
  auto value = [&](std::string& dst) {
    if (i + 1 >= argc || argv[i + 1][0] == '-') return false;
    dst = argv[++i];
    return true;
  };
  std::string v;
  if (const auto imu_problem = parseImuOption(a, argc, argv, i, args.imu)) return *imu_problem;
  if (const auto doppler_problem = parseDopplerOption(a, argc, argv, i, args.imu)) return *doppler_problem;
  if (a == "--obs") {
    if (!req.files.obs.empty() || !value(req.files.obs)) return "--obs needs a file (and no --rtcm/--ubx)";
  } else if (a == "--rtcm") {  // an RTCM 3 recording (MSM) as the observations
    if (!req.files.obs.empty() || !value(req.files.obs)) return "--rtcm needs an RTCM 3 file (and no --obs/--ubx)";
    req.files.obs_format = ppp::ObservationFormat::Rtcm3;
  } else if (a == "--ref-date") {
    if (!value(v) || !(req.files.rtcm_reference_time = ppp::parseReferenceDate(v))) return "--ref-date needs YYYY/MM/DD";
  } else if (a == "--ubx") {  // a u-blox UBX recording (RXM-RAWX) as the observations
    if (!req.files.obs.empty() || !value(req.files.obs)) return "--ubx needs a file (and no --obs/--rtcm)";
    req.files.obs_format = ppp::ObservationFormat::Ubx;
  } else if (a == "--start" || a == "--end") {  // GPST window [start, end)
    std::optional<ppp::GnssTime>& bound = a == "--start" ? req.files.window.start : req.files.window.end;
    if (i + 1 >= argc || !(bound = ppp::parseReferenceDate(argv[++i])))
      return a + " needs a GPST time YYYY/MM/DD or \"YYYY/MM/DD HH:MM:SS\"";
  } else if (a == "--gnss-gap") {  // "YYYY/MM/DD HH:MM:SS,SECONDS": epochs kept without satellites
    const std::string text = i + 1 < argc ? argv[++i] : "";
    const auto comma = text.rfind(',');
    char* end = nullptr;
    const double seconds = comma == std::string::npos ? 0.0 : std::strtod(text.c_str() + comma + 1, &end);
    if (comma == std::string::npos || !(req.files.window.outage_start = ppp::parseReferenceDate(text.substr(0, comma))) ||
        end == text.c_str() + comma + 1 || *end != '\0' || !(seconds > 0.0) || !std::isfinite(seconds))
      return "--gnss-gap needs \"YYYY/MM/DD HH:MM:SS,SECONDS\" (GPST start, duration > 0)";
    req.files.window.outage_s = seconds;
  } else if (a == "--no-product-checks") {
    req.files.check_products = false;
  } else if (a == "--bia" || a == "--ssr" || a == "--blq") {
    if (!value(v)) return a + (a == "--ssr" ? " needs an RTCM SSR stream file" : " needs a file");
    (a == "--bia" ? req.files.bias : a == "--ssr" ? req.files.ssr : req.files.blq) = v;
  } else if (a == "--ssr-reference") {
    // com | apc (= apc-if: the ionosphere-free phase centre) | apc-l1 (IGS SSRA);
    // models/satellite_reference_point.h
    if (!value(v) || !(req.files.ssr_reference = ppp::parseEphemerisReference(v)))
      return "--ssr-reference needs com, apc (apc-if) or apc-l1";
  } else if (a == "--estimator") {
    if (!value(req.estimator))
      return "--estimator needs " + ppp::registeredEstimatorNames(", ") + " or " + std::string(ppp::kAllEstimators);
  } else if (a == "--truth") {
    Eigen::Vector3d t;
    if (i + 1 >= argc || !parseTruth(argv[++i], t)) return "--truth needs X,Y,Z in metres (ECEF)";
    req.truth_ecef_m = t;
  } else if (a == "--name") {
    if (!value(req.name)) return "--name needs a text";
  } else if (a == "--out") {
    if (!value(req.out_dir)) return "--out needs a directory";
  } else {
    return "unknown option " + a;
  }
  return {};
}

/// The multi-file option `a` fills (--sp3, --clk, --nav, --atx, --config), or null.
std::vector<std::string>* fileList(const std::string& a, SolveArgs& args) {
  if (a == "--sp3") return &args.req.files.sp3;
  if (a == "--clk") return &args.req.files.clk;
  if (a == "--nav") return &args.req.files.nav;
  if (a == "--atx") return &args.req.files.atx;
  if (a == "--config") return &args.config_paths;
  return nullptr;
}

/// Parses the command line: nullopt when the run goes on, else the exit status
/// (2 for a usage error, 0 for --help).
std::optional<int> parseArguments(int argc, char** argv, SolveArgs& args) {
  std::vector<std::string>* list = nullptr;  // the multi-file option being filled
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (std::vector<std::string>* files = fileList(a, args)) {
      list = files;
      if (i + 1 >= argc || argv[i + 1][0] == '-') return usage(a + " needs at least one file");
      continue;
    }
    if (!a.empty() && a[0] != '-') {
      if (!list) return usage("unexpected argument '" + a + "'");
      list->push_back(a);
      continue;
    }
    list = nullptr;
    if (a == "-h" || a == "--help") {
      usage("help");
      return 0;
    }
    if (const std::string why = parseOption(a, argc, argv, i, args); !why.empty()) return usage(why);
  }
  return std::nullopt;
}

/// What is missing or inconsistent in the parsed arguments; empty when nothing.
std::string argumentsProblem(const SolveArgs& args) {
  const ppp::PppSolveRequest& req = args.req;
  if (std::string why; !ppp::selectEstimators(req.estimator, &why)) return "--estimator: " + why;
  if (std::string why = imuUsageProblem(req.estimator, args.imu); !why.empty()) return why;
  if (req.files.obs.empty()) return "one of --obs, --rtcm and --ubx is required";
  if (std::string why = ppp::fileProductInputsProblem(ppp::productInputsGiven(req.files)); !why.empty()) return why;
  if (req.files.atx.empty()) return "--atx is required";
  if (req.out_dir.empty()) return "--out is required";
  if (req.files.window.start && req.files.window.end && *req.files.window.end <= *req.files.window.start)
    return "--end must be after --start";
  return {};
}

/// Prints one run's report and its written files.
void printRun(const ppp::PppSolveOutcome& out) {
  std::cout << "=== estimator " << out.run.estimator << " ===\n" << ppp::formatRunReport(out.run);
  if (out.update_time) {
    std::printf("smoother per epoch (%zu solved epochs): iSAM2 update median %.2f ms, p99 %.2f ms, max %.2f ms; "
                "estimator step median %.2f ms, p99 %.2f ms\n",
                out.update_time->count, out.update_time->median_s * 1e3, out.update_time->p99_s * 1e3,
                out.update_time->max_s * 1e3, out.epoch_time->median_s * 1e3, out.epoch_time->p99_s * 1e3);
  }
  std::cout << "written:";
  for (const auto& o : out.outputs) std::cout << "\n  " << o.csv_path << "\n  " << o.pos_path << "\n  " << o.json_path;
  std::cout << "\n  " << out.epochs_path << "\n  " << out.residuals_path;
  if (!out.biases_path.empty()) std::cout << "\n  " << out.biases_path;
  std::cout << "\n\n";
}

/// Prints the statistics table of the solutions with a truth (one or a comparison).
void printStatistics(const std::vector<ppp::PppSolveOutcome>& runs) {
  std::vector<std::pair<std::string, ppp::PositionErrorStatistics>> columns;
  for (const auto& out : runs)
    for (const auto& o : out.outputs)
      if (o.statistics) columns.emplace_back(o.label, *o.statistics);
  if (columns.size() == 1) std::cout << ppp::formatStatisticsTable(columns[0].second, runs[0].name + " " + columns[0].first);
  if (columns.size() > 1) std::cout << runs[0].name << ":\n" << ppp::formatStatisticsComparison(columns);
  std::cout.flush();
}

/// 1 when a run solved nothing, 3 when one had input problems, else 0.
int exitStatus(const std::vector<ppp::PppSolveOutcome>& runs) {
  for (const auto& out : runs)
    if (out.run.epochs_solved == 0) return 1;
  for (const auto& out : runs)
    if (!out.run.problems.empty()) {
      std::cerr << "ppp_solve: solved, with " << out.run.problems.size()
                << " input problem(s) (listed under 'problems' above and in the summary JSON): exit status 3\n";
      return 3;
    }
  return 0;
}

/// Loads the configuration and the IMU, runs the estimators and prints their reports.
int solve(SolveArgs& args) {
  ppp::PppSolveRequest& req = args.req;
  if (!args.config_paths.empty()) req.config = ppp::loadPppConfig(args.config_paths);
  req.config.ins = args.imu.ins;
  if (!args.imu.file.path.empty()) req.imu = readImu(args.imu);
  const bool tty = isatty(STDERR_FILENO) != 0;
  if (tty) req.on_epoch = drawProgress;
  const std::vector<ppp::PppSolveOutcome> runs = ppp::solvePppEstimators(req);
  if (tty) std::fprintf(stderr, "\n");
  for (const auto& out : runs) printRun(out);
  printStatistics(runs);
  return exitStatus(runs);
}

}  // namespace

int main(int argc, char** argv) {
  SolveArgs args;
  if (const std::optional<int> status = parseArguments(argc, argv, args)) return *status;
  if (const std::string why = argumentsProblem(args); !why.empty()) return usage(why);
  try {
    return solve(args);
  } catch (const ppp::ConfigError& e) {
    std::cerr << "ppp_solve: configuration: " << e.what() << "\n";
  } catch (const std::exception& e) {  // ParseError, FileOpenError (name the file and line) and the rest
    std::cerr << "ppp_solve: " << e.what() << "\n";
  }
  return 1;
}
