// The tool ppp_campaign as a user runs it (a process started here): its numeric
// options, the output directory of another campaign, and a stop (a signal to
// the campaign, or the campaign killed) reaching its running jobs. The tool is
// the one built beside this test (devel/lib/ppp_bayes_tree); without it the tests
// skip with the reason.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include "ppp_bayes_tree/app/campaign_job.h"
#include "ppp_bayes_tree/app/campaign_summary.h"
#include "ppp_bayes_tree/app/child_process.h"
#include "test_support.h"

using namespace ppp;
namespace fs = std::filesystem;

namespace {

std::string campaignTool() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const fs::path beside = self.parent_path() / "ppp_campaign";
  return !ec && fs::exists(beside) ? beside.string() : "";
}

#define REQUIRE_CAMPAIGN_TOOL()                                                   \
  if (campaignTool().empty()) GTEST_SKIP() << "ppp_campaign is not built beside this test"

struct ToolRun {
  int exit_status = -1;
  std::string output;
};

/// Runs ppp_campaign with `args` to its end; its standard output and error together.
ToolRun runTool(const std::vector<std::string>& args) {
  ChildProcessSpec spec;
  spec.argv = {campaignTool()};
  spec.argv.insert(spec.argv.end(), args.begin(), args.end());
  spec.stderr_to = ChildStream::withStdout();
  const CapturedOutput run = runCapturingOutput(spec);
  return {run.end.exited() ? run.end.exit_status : 128 + run.end.signal, run.output};
}

fs::path writeFile(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
  return p;
}

/// A Monte Carlo study of one short flight: a campaign of one quick job.
std::string quickCampaign(const std::string& name) {
  return "campaign: {name: " + name + "}\nmonte_carlo:\n  - {study: s, seed: 3, flights: 1, duration_min: 1}\n";
}

/// One job that runs for minutes (a day-long flight): stopped by the tests long before it ends.
const char* kLongCampaign = "campaign: {name: long}\nmonte_carlo:\n  - {study: day, seed: 3, flights: 1, duration_min: 1440}\n";

/// Waits up to `timeout_s` for `condition`.
template <class Condition>
bool waitFor(Condition condition, double timeout_s) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!condition()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

/// Starts `ppp_campaign run` of the long campaign into `out`, and waits until its job runs (holds its lock).
ChildProcess startLongCampaign(const fs::path& dir, const fs::path& out, std::string& job_dir) {
  const fs::path manifest = writeFile(dir / "long.yaml", kLongCampaign);
  ChildProcessSpec spec;
  spec.argv = {campaignTool(), "run", manifest.string(), "--out", out.string(), "--jobs", "1", "--no-plot"};
  spec.stdout_to = ChildStream::file((dir / "campaign.log").string());
  spec.stderr_to = ChildStream::withStdout();
  ChildProcess campaign = ChildProcess::spawn(spec);
  job_dir = campaignJobDir(out.string(), "day_f0-0");
  EXPECT_TRUE(waitFor([&] { return campaignJobLocked(job_dir); }, 30.0)) << "the job never started";
  return campaign;
}

}  // namespace

TEST(CampaignTool, NumericOptionsAreWholeNumbers) {
  REQUIRE_CAMPAIGN_TOOL();
  const fs::path dir = test::tempDir("campaign_tool_numbers");
  const std::string m = writeFile(dir / "m.yaml", quickCampaign("n")).string();
  for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
           {"--jobs", "2abc"}, {"--jobs", "0"}, {"--jobs", "-1"}, {"--jobs", "99999999999"}, {"--jobs-per-task", "3.5"},
           {"--max-resubmits", "-1"}, {"--max-resubmits", "1x"}, {"--poll-s", "1s"}, {"--poll-s", "nan"},
           {"--poll-s", "0"}}) {
    const ToolRun r = runTool({"run", m, "--out", (dir / "out").string(), option, value});
    EXPECT_EQ(r.exit_status, 2) << option << " " << value << ": " << r.output;
    EXPECT_NE(r.output.find(option + " needs"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("'" + value + "'"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_EQ(runTool({"check", m, "--jobs", "2", "--poll-s", "0.5", "--max-resubmits", "0"}).exit_status, 0);
}

TEST(CampaignTool, AnOutputDirectoryOfAnotherCampaignIsRefused) {
  REQUIRE_CAMPAIGN_TOOL();
  const fs::path dir = test::tempDir("campaign_tool_out");
  const std::string a = writeFile(dir / "a.yaml", quickCampaign("alpha")).string();
  const std::string b = writeFile(dir / "b.yaml", quickCampaign("beta")).string();
  const std::string out = (dir / "out").string();
  ASSERT_EQ(runTool({"run", a, "--out", out, "--no-plot"}).exit_status, 0);
  const std::string manifest_before = test::readFileBytes(out + "/manifest.yaml");
  const std::string summary_before = test::readFileBytes(out + "/summary.json");

  for (const char* command : {"run", "summary"}) {
    const ToolRun other = runTool({command, b, "--out", out, "--no-plot"});
    EXPECT_EQ(other.exit_status, 2) << other.output;
    EXPECT_NE(other.output.find("holds the campaign 'alpha'"), std::string::npos) << other.output;
    EXPECT_EQ(test::readFileBytes(out + "/manifest.yaml"), manifest_before);
    EXPECT_EQ(test::readFileBytes(out + "/summary.json"), summary_before);
  }
  // the same campaign resumes
  const ToolRun again = runTool({"run", a, "--out", out, "--no-plot"});
  EXPECT_EQ(again.exit_status, 0) << again.output;
  EXPECT_NE(again.output.find("1 jobs: 1 already done, 0 to run"), std::string::npos) << again.output;
  // a directory of other files is no campaign's
  fs::create_directories(dir / "home");
  writeFile(dir / "home" / "notes.txt", "mine\n");
  const ToolRun foreign = runTool({"run", a, "--out", (dir / "home").string(), "--no-plot"});
  EXPECT_EQ(foreign.exit_status, 2) << foreign.output;
  EXPECT_NE(foreign.output.find("other files and no campaign"), std::string::npos) << foreign.output;
  EXPECT_FALSE(fs::exists(dir / "home" / "jobs"));
}

TEST(CampaignTool, AStopSignalReachesTheRunningJobs) {
  REQUIRE_CAMPAIGN_TOOL();
  for (const int sig : {SIGTERM, SIGINT, SIGHUP}) {
    struct sigaction now {};
    if (::sigaction(sig, nullptr, &now) == 0 && now.sa_handler == SIG_IGN) continue;  // ignored by whoever started us
    const fs::path dir = test::tempDir("campaign_tool_stop_" + std::to_string(sig));
    std::string job_dir;
    ChildProcess campaign = startLongCampaign(dir, dir / "out", job_dir);
    campaign.kill(sig);
    bool ended = waitFor([&] { return campaign.poll().has_value(); }, 20.0);
    if (!ended) campaign.kill(SIGKILL);
    ASSERT_TRUE(ended) << "the campaign did not end after signal " << sig;
    EXPECT_EQ(campaign.end()->exit_status, 128 + sig) << test::readFileBytes((dir / "campaign.log").string());
    EXPECT_FALSE(campaignJobLocked(job_dir)) << "the job's process outlived the campaign";
    EXPECT_FALSE(fs::exists(fs::path(job_dir) / "done.json"));
    const std::string failed = test::readFileBytes(job_dir + "/failed.json");
    EXPECT_NE(failed.find("killed by signal " + std::to_string(sig)), std::string::npos) << failed;
    EXPECT_NE(failed.find("the campaign was stopped by signal " + std::to_string(sig)), std::string::npos) << failed;
    EXPECT_NE(test::readFileBytes((dir / "out" / "summary.csv").string()).find("day_f0-0,monte_carlo,day,,,failed"),
              std::string::npos);
  }
}

TEST(CampaignTool, AKilledCampaignTakesItsJobsAlong) {
  REQUIRE_CAMPAIGN_TOOL();
  const fs::path dir = test::tempDir("campaign_tool_kill9");
  std::string job_dir;
  ChildProcess campaign = startLongCampaign(dir, dir / "out", job_dir);
  // The attempt has begun (its work folder exists: a job killed between taking
  // its lock and that is still pending, not interrupted).
  EXPECT_TRUE(waitFor([&] { return fs::exists(fs::path(job_dir) / "work"); }, 30.0));
  campaign.kill(SIGKILL);
  campaign.wait();
  EXPECT_TRUE(waitFor([&] { return !campaignJobLocked(job_dir); }, 10.0))
      << "the job's process still runs after its campaign was killed";
  EXPECT_FALSE(fs::exists(fs::path(job_dir) / "done.json"));
  EXPECT_EQ(campaignJobStatus(job_dir).state, CampaignJobState::Interrupted);
}
