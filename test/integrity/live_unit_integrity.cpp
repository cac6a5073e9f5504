// Integrity of the live node inputs and the configuration, fast cases (no roscore):
// each finding with the clean and the faulty input side by side.
//  * NTRIP credentials: maskCredentials on mistyped specs, parse errors without the
//    password, credentials from a file readable by its owner only or the environment;
//  * a caster's status line with ESC sequences reaches no message raw (printableText);
//  * absurd but well-typed configuration values refused with the key path and range;
//  * file:// of a directory refused at start-up (was: "file ended");
//  * launch/live.launch: receiver_spec:='' starts no receiver stream node;
//  * launch/ppp_smoother.launch: a bounded (fixed-lag) smoother by default, the full one on request.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "loopback_servers.h"
#include "test_support.h"
#include "ppp_bayes_tree/io/transport/byte_source_spec.h"
#include "ppp_bayes_tree/io/transport/credential_mask.h"
#include "ppp_bayes_tree/io/transport/ntrip_client_source.h"
#include "ppp_bayes_tree/io/transport/ntrip_credentials.h"
#include "ppp_bayes_tree/io/untrusted_text.h"
#include "ppp_bayes_tree/ppp/config/ppp_config.h"
#include "ppp_bayes_tree/ros/node_options.h"

namespace {

using namespace std::chrono_literals;
const std::string kPassword = "Pw4Test-Zq9";

std::filesystem::path tempDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("ppp_integrity_live_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// --- the password ------------------------------------------------------------------

TEST(LiveSecrets, MaskCredentialsHidesThePasswordOfEveryMistypedSpec) {
  // Clean: a spec without userinfo, and one masked already, are unchanged.
  EXPECT_EQ(ppp::maskCredentials("ntrip://rover@caster:2101/M"), "ntrip://rover@caster:2101/M");
  EXPECT_EQ(ppp::maskCredentials("tcp://10.0.0.1:5018"), "tcp://10.0.0.1:5018");
  EXPECT_EQ(ppp::maskCredentials("ntrip://rover:***@caster/M"), "ntrip://rover:***@caster/M");
  EXPECT_EQ(ppp::maskCredentials("ntrip://rover:" + kPassword + "@caster:2101/M?version=2"),
            "ntrip://rover:***@caster:2101/M?version=2");
  // Faulty: the four mistypings reported, and passwords holding '@', '/', ':' and '?'.
  for (const std::string& spec :
       {"NTRIP://rover:" + kPassword + "@caster:2101/M", " ntrip://rover:" + kPassword + "@caster:2101/M",
        "ntrip:/rover:" + kPassword + "@caster:2101/M", "ntrip://rover:" + kPassword + "?x@caster:2101/M",
        "ntrip://rover:" + kPassword + "@x@caster/M", "ntrip://rover:" + kPassword + "/x@caster/M",
        "ntrip://rover:" + kPassword + ":x@caster/M", "ntrip//rover:" + kPassword + "@caster/M",
        "input spec 'ntrip://rover:" + kPassword + "@caster/M': no mountpoint"}) {
    const std::string shown = ppp::maskCredentials(spec);
    EXPECT_EQ(shown.find(kPassword), std::string::npos) << spec << " -> " << shown;
    EXPECT_NE(shown.find("***@"), std::string::npos) << spec << " -> " << shown;
  }
}

TEST(LiveSecrets, ParseErrorsOfMistypedSpecsNeverHoldThePassword) {
  const std::string good = "ntrip://rover:" + kPassword + "@127.0.0.1:2101/MOUNT";
  EXPECT_NO_THROW(ppp::parseByteSourceSpec(good));
  // Each of these was refused with the password in the message (main 21783f2).
  for (const std::string& spec :
       {"NTRIP://rover:" + kPassword + "@127.0.0.1:2101/MOUNT", " ntrip://rover:" + kPassword + "@127.0.0.1:2101/MOUNT",
        "ntrip:/rover:" + kPassword + "@127.0.0.1:2101/MOUNT", std::string("ntrip://rover:Pw4?Test-Zq9@127.0.0.1:2101/MOUNT"),
        "ntrip://rover:" + kPassword + "@127.0.0.1:2101/MOUNT?bogus=1"}) {
    try {
      ppp::parseByteSourceSpec(spec);
      ADD_FAILURE() << "accepted: " << ppp::maskCredentials(spec);
    } catch (const ppp::ByteSourceSpecError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find(kPassword), std::string::npos) << what;
      EXPECT_EQ(what.find("Test-Zq9"), std::string::npos) << what;  // the part after an unescaped '?'
    }
  }
}

class CredentialsFile : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& content, mode_t mode) {
    const auto path = tempDir("credentials") / "ntrip";
    std::ofstream(path) << content;
    ::chmod(path.c_str(), mode);
    return path;
  }
};

TEST_F(CredentialsFile, OwnerOnlyFileGivesUserAndPasswordGroupReadableIsRefused) {
  // Clean: mode 0600, a comment line first.
  auto path = write("# caster account\nrover:" + kPassword + "\n", 0600);
  ppp::ByteSourceSpec spec = ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M?credentials=" + path.string());
  EXPECT_EQ(spec.text_without_password.find(kPassword), std::string::npos);
  EXPECT_EQ(ppp::resolveNtripCredentials(spec, nullptr), ppp::CredentialSource::File);
  EXPECT_EQ(spec.user, "rover");
  EXPECT_EQ(spec.password, kPassword);
  // Faulty: readable by the group (0640) and by everyone (0644): refused like ssh does, naming the mode.
  for (const mode_t mode : {mode_t{0640}, mode_t{0644}, mode_t{0606}}) {
    path = write("rover:" + kPassword + "\n", mode);
    spec = ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M?credentials=" + path.string());
    try {
      ppp::resolveNtripCredentials(spec, nullptr);
      ADD_FAILURE() << "mode " << std::oct << mode << " accepted";
    } catch (const ppp::ByteSourceSpecError& e) {
      EXPECT_NE(std::string(e.what()).find("chmod 600"), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find(kPassword), std::string::npos) << e.what();
    }
  }
  // A password in the spec and credentials= both: refused; a user differing: refused.
  path = write("rover:" + kPassword + "\n", 0600);
  spec = ppp::parseByteSourceSpec("ntrip://rover:other@127.0.0.1:2101/M?credentials=" + path.string());
  EXPECT_THROW(ppp::resolveNtripCredentials(spec, nullptr), ppp::ByteSourceSpecError);
  spec = ppp::parseByteSourceSpec("ntrip://alice@127.0.0.1:2101/M?credentials=" + path.string());
  EXPECT_THROW(ppp::resolveNtripCredentials(spec, nullptr), ppp::ByteSourceSpecError);
}

TEST_F(CredentialsFile, EnvironmentVariableGivesThemWhenTheSpecHasNoPassword) {
  const std::string value = "rover:" + kPassword;
  ppp::ByteSourceSpec spec = ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M");
  EXPECT_EQ(ppp::resolveNtripCredentials(spec, value.c_str()), ppp::CredentialSource::Environment);
  EXPECT_EQ(spec.user, "rover");
  EXPECT_EQ(spec.password, kPassword);
  // The spec's own password wins (and is reported as such); no ':' in the variable: refused.
  spec = ppp::parseByteSourceSpec("ntrip://rover:inline@127.0.0.1:2101/M");
  EXPECT_EQ(ppp::resolveNtripCredentials(spec, value.c_str()), ppp::CredentialSource::Spec);
  EXPECT_EQ(spec.password, "inline");
  spec = ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M");
  EXPECT_THROW(ppp::resolveNtripCredentials(spec, "rover"), ppp::ByteSourceSpecError);
}

TEST_F(CredentialsFile, LineEndsAreRemovedAlikeAndAnEmptyPasswordIsRefused) {
  // A CR (or CR LF) after the password: removed from the variable as from the file.
  for (const std::string end : {"\r", "\r\n", "\n"}) {
    const std::string value = "rover:" + kPassword + end;
    ppp::ByteSourceSpec spec = ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M");
    EXPECT_EQ(ppp::resolveNtripCredentials(spec, value.c_str()), ppp::CredentialSource::Environment);
    EXPECT_EQ(spec.password, kPassword) << "line end " << end.size() << " characters";
    const auto path = write(value, 0600);
    spec = ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M?credentials=" + path.string());
    EXPECT_EQ(ppp::resolveNtripCredentials(spec, nullptr), ppp::CredentialSource::File);
    EXPECT_EQ(spec.password, kPassword);
  }
  // "alice:" (nothing after the ':'): refused from both, naming where it came from.
  const auto refusal = [](ppp::ByteSourceSpec spec, const char* env) {
    try {
      ppp::resolveNtripCredentials(spec, env);
    } catch (const ppp::ByteSourceSpecError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string env = refusal(ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M"), "alice:\r");
  EXPECT_NE(env.find("PPP_NTRIP_CREDENTIALS holds an empty password"), std::string::npos) << env;
  const auto path = write("alice:\n", 0600);
  const std::string file =
      refusal(ppp::parseByteSourceSpec("ntrip://127.0.0.1:2101/M?credentials=" + path.string()), nullptr);
  EXPECT_NE(file.find(path.string() + " holds an empty password"), std::string::npos) << file;
}

// --- network text ------------------------------------------------------------------

TEST(LiveUntrustedText, PrintableTextEscapesControlsAndCutsLongText) {
  EXPECT_EQ(ppp::printableText("HTTP/1.1 200 OK"), "HTTP/1.1 200 OK");
  EXPECT_EQ(ppp::printableText("A\x1b[2J\x1b[31mB\\\t\x7f\xff"), "A\\x1b[2J\\x1b[31mB\\\\\\t\\x7f\\xff");
  const std::string long_text(1000, 'x');
  const std::string shown = ppp::printableText(long_text);
  EXPECT_LT(shown.size(), 250u);
  EXPECT_NE(shown.find("(1000 bytes)"), std::string::npos);
}

/// The error of an NTRIP client whose caster answers `status_line`.
ppp::ByteSourceError casterError(const std::string& status_line) {
  ppp::test::ScriptedServer server([status_line](int fd, const std::atomic<bool>&) {
    ppp::test::ScriptedServer::readRequest(fd);
    ppp::test::ScriptedServer::sendAll(fd, status_line + "\r\nContent-Length: 0\r\n\r\n");
  });
  ppp::NtripClientOptions o;
  o.host = "127.0.0.1";
  o.port = server.port();
  o.mountpoint = "M";
  o.user = "rover";
  o.password = kPassword;
  o.connect_timeout = 2000ms;
  o.stall_timeout = 2000ms;
  ppp::NtripClientSource client(o);
  std::uint8_t buffer[64];
  const ppp::ByteSourceRead got = client.read(buffer, sizeof buffer, 2000ms);
  EXPECT_EQ(got.status, ppp::ByteSourceStatus::Error);
  return got.error.value_or(ppp::ByteSourceError{});
}

TEST(LiveUntrustedText, CasterStatusLineWithEscapeSequencesIsEscapedInTheError) {
  // Clean: a plain refusal reads as it came.
  const ppp::ByteSourceError clean = casterError("HTTP/1.1 401 Unauthorized");
  EXPECT_NE(clean.describe().find("(HTTP/1.1 401 Unauthorized)"), std::string::npos) << clean.describe();
  // Faulty: ESC sequences (clear screen, red) and a bell: shown as \x1b..., never raw.
  for (const std::string& line : {std::string("HTTP/1.1 401 \x1b[2J\x1b[31mGo away\x07"),
                                  std::string("HTTP/1.1 500 \x1b]0;owned\x07"), std::string("ICY 4\x1b[1mXX")}) {
    const std::string text = casterError(line).describe();
    for (const char c : text) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "raw byte " << int(c) << " in " << text;
    EXPECT_NE(text.find("\\x1b"), std::string::npos) << text;
    EXPECT_EQ(text.find(kPassword), std::string::npos) << text;
  }
}

// --- absurd values ------------------------------------------------------------------

/// The ConfigError of `yaml` bound as config/ppp.yaml (+ its ros: section), or "" when accepted.
std::string configError(const std::string& yaml) {
  try {
    const ppp::PppConfig c = ppp::parsePppConfig(yaml, "test.yaml");
    ppp_ros::bindRosNodeOptions(c.ros, "test.yaml");
  } catch (const ppp::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(LiveConfigRanges, AbsurdWellTypedValuesAreRefusedWithKeyPathAndRange) {
  struct Case {
    const char* clean;
    const char* faulty;
    const char* key_path;
  };
  const Case cases[] = {
      {"smoother: {fixed_lag_s: 60.0}", "smoother: {fixed_lag_s: 1.0e+9}", "smoother.fixed_lag_s"},
      {"estimator: {min_satellites: 6}", "estimator: {min_satellites: 1000}", "estimator.min_satellites"},
      {"stochastic: {position: {initial_sigma_m: 100.0}}", "stochastic: {position: {initial_sigma_m: 1.0e+300}}",
       "stochastic.position.initial_sigma_m"},
      {"ros: {input: {correction_wait_s: 60.0}}", "ros: {input: {correction_wait_s: 1.0e+9}}",
       "ros.input.correction_wait_s"},
      {"ros: {live: {correction_wait_s: 20.0}}", "ros: {live: {correction_wait_s: 1.0e+9}}",
       "ros.live.correction_wait_s"},
      {"ros: {diagnostics: {path_max_poses: 6000}}", "ros: {diagnostics: {path_max_poses: 100000000}}",
       "ros.diagnostics.path_max_poses"},
      {"cycle_slip: {geometry_free: {fit_points: 5}}", "cycle_slip: {geometry_free: {fit_points: 100000}}",
       "cycle_slip.geometry_free.fit_points"},
      {"measurement_model: {code_phase_ratio: 100.0}", "measurement_model: {code_phase_ratio: 1.0e+12}",
       "measurement_model.code_phase_ratio"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(configError(c.clean), "") << c.clean;
    const std::string error = configError(c.faulty);
    EXPECT_NE(error.find(std::string(c.key_path) + ": must be in "), std::string::npos) << c.faulty << " -> " << error;
  }
  // Every shipped configuration stays within the ranges.
  for (const char* file : {"ppp.yaml", "live.yaml", "ppp_real_data.yaml", "ppp_ros_zim2.yaml", "ppp_simulated.yaml",
                           "method_table.yaml"}) {
    const std::string path = std::string(PPP_REPO_DIR) + "/config/" + file;
    EXPECT_NO_THROW(ppp::loadPppConfig(std::vector<std::string>{std::string(PPP_REPO_DIR) + "/config/ppp.yaml", path}))
        << path;
  }
}

/// ppp_solve's exit code and output (stdout + stderr) on the ZIM2 hour with `config` laid over config/ppp.yaml.
int solveZim2(const std::string& config, const std::string& estimator, std::string* output) {
  const std::string d = ppp::test::dataPath("zim2-2026-133");
  const auto dir = tempDir("zim2_" + estimator);
  const auto yaml = dir / "bounds.yaml";
  std::ofstream(yaml) << config;
  const std::string command = std::string(PPP_BIN_DIR) + "/ppp_solve --obs " + d +
                              "/ZIM200CHE_R_20261330000_01H_30S_MO.rnx --sp3 " + d +
                              "/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3 --clk " + d +
                              "/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK --atx " +
                              ppp::test::dataPath("antex/igs20_zim2_gps_trim.atx") + " --bia " + d +
                              "/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz --config " + PPP_REPO_DIR +
                              "/config/ppp.yaml " + yaml.string() + " --estimator " + estimator + " --out " +
                              dir.string() + " 2>&1";
  output->clear();
  FILE* p = ::popen(command.c_str(), "r");
  if (!p) return -1;
  std::array<char, 4096> buffer{};
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), p)) output->append(buffer.data(), n);
  return WEXITSTATUS(::pclose(p));
}

TEST(LiveConfigRanges, BothEstimatorsSolveEveryZim2EpochAtTheStochasticBoundsAndBeyondIsRefused) {
  PPP_REQUIRE_SHARED_DATA();
  // At the upper bounds of the a priori sigmas both estimators solve all 120 epochs of the hour
  // (the data README: 120 epochs); 1e300 made the EKF fail every epoch while the smoother solved them.
  const std::string at_bounds =
      "stochastic:\n  position: {initial_sigma_m: 10000.0, process_noise_m_per_sqrt_s: 1000.0}\n"
      "  clock: {initial_sigma_m: 1.0e+8}\n  phase_bias: {initial_sigma_m: 10000.0}\n  zwd: {initial_sigma_m: 10.0}\n";
  for (const std::string estimator : {"ekf", "smoother"}) {
    std::string out;
    EXPECT_EQ(solveZim2(at_bounds, estimator, &out), 0) << out;
    EXPECT_NE(out.find("epochs: 120 read, 120 solved"), std::string::npos) << estimator << ": " << out;
  }
  std::string out;
  EXPECT_NE(solveZim2("stochastic:\n  position: {initial_sigma_m: 1.0e+300}\n", "ekf", &out), 0) << out;
  EXPECT_NE(out.find("stochastic.position.initial_sigma_m: must be in (0, 10000]"), std::string::npos) << out;
}

TEST(LiveConfigRanges, FileSpecOfADirectoryIsRefusedAtStart) {
  const auto dir = tempDir("file_spec");
  const auto file = dir / "x.rtcm3";
  std::ofstream(file) << "";
  EXPECT_NO_THROW(ppp::openByteSource(ppp::parseByteSourceSpec("file://" + file.string())));
  try {
    ppp::openByteSource(ppp::parseByteSourceSpec("file://" + dir.string()));
    ADD_FAILURE() << "a directory was opened as a recording";
  } catch (const ppp::ByteSourceSpecError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

// --- launch files ------------------------------------------------------------------

/// The output of a roslaunch inspection command (--nodes, --dump-params), stderr dropped.
std::string roslaunch(const std::string& args) {
  const std::string command = "roslaunch " + args + " 2>/dev/null";
  std::string out;
  if (FILE* p = ::popen(command.c_str(), "r")) {
    std::array<char, 4096> buffer{};
    while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), p)) out.append(buffer.data(), n);
    ::pclose(p);
  }
  return out;
}

TEST(LiveLaunch, EmptyReceiverSpecStartsNoReceiverStreamNode) {
  const std::string launch = std::string(PPP_REPO_DIR) + "/launch/live.launch";
  const std::string given = roslaunch("--nodes " + launch + " example:=b receiver_spec:=serial:///dev/ttyUSB7");
  ASSERT_NE(given.find("/smoother/ppp_smoother_node"), std::string::npos) << "roslaunch --nodes failed: " << given;
  EXPECT_NE(given.find("/receiver_stream"), std::string::npos) << given;
  // roslaunch drops `receiver_spec:=` (empty) and applies the default: that must be "none".
  EXPECT_EQ(roslaunch("--nodes " + launch + " example:=b receiver_spec:=").find("/receiver_stream"), std::string::npos);
  EXPECT_EQ(roslaunch("--nodes " + launch + " example:=b").find("/receiver_stream"), std::string::npos);
}

TEST(LiveLaunch, SmootherLaunchIsBoundedByDefaultAndWritesTheStatesLeavingTheLag) {
  const std::string launch = std::string(PPP_REPO_DIR) + "/launch/ppp_smoother.launch";
  const std::string bounded = roslaunch("--dump-params " + launch);
  ASSERT_NE(bounded.find("/smoother/ppp_smoother_node/smoother/fixed_lag_s:"), std::string::npos) << bounded;
  EXPECT_NE(bounded.find("/smoother/ppp_smoother_node/smoother/fixed_lag_s: 60.0"), std::string::npos) << bounded;
  EXPECT_NE(bounded.find("/smoother/ppp_smoother_node/ros/smoothed/trajectory_csv: smoothed_trajectory.csv"),
            std::string::npos);
  const std::string full = roslaunch("--dump-params " + launch + " smoother_memory:=full");
  EXPECT_NE(full.find("/smoother/ppp_smoother_node/smoother/fixed_lag_s: 0.0"), std::string::npos) << full;
}

}  // namespace
