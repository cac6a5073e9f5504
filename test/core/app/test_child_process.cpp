// Child processes (app/child_process.h), with real processes of /bin/sh: how a
// child ended (exit status, a signal), a start that cannot happen (no such
// executable, not executable, an output file or working directory that cannot be
// used: nothing runs), where the output goes (files, /dev/null, 2>&1, a pipe),
// the environment and working directory, and a running child killed, waited for
// among others, or dropped.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "ppp_bayes_tree/app/child_process.h"
#include "test_support.h"

using namespace ppp;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

ChildProcessSpec shell(const std::string& script) {
  ChildProcessSpec spec;
  spec.argv = {"/bin/sh", "-c", script};
  return spec;
}

/// Whether a process with this id exists (a zombie counts: it is not collected).
bool processExists(pid_t pid) { return ::kill(pid, 0) == 0 || errno != ESRCH; }

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

TEST(ChildProcess, ExitStatusIsReported) {
  const ProcessEnd ok = runChildProcess(shell("exit 0"));
  EXPECT_TRUE(ok.exited());
  EXPECT_TRUE(ok.succeeded());
  EXPECT_EQ(ok.exit_status, 0);
  const ProcessEnd three = runChildProcess(shell("exit 3"));
  EXPECT_TRUE(three.exited());
  EXPECT_FALSE(three.succeeded());
  EXPECT_EQ(three.exit_status, 3);
  EXPECT_EQ(three.signal, 0);
  EXPECT_EQ(three.text(), "exited with status 3");
}

TEST(ChildProcess, DeathBySignalIsReportedWithTheSignal) {
  // The shell sends itself SIGUSR1, whose default action ends the process.
  const ProcessEnd end = runChildProcess(shell("kill -USR1 $$; sleep 5; exit 0"));
  EXPECT_FALSE(end.exited());
  EXPECT_FALSE(end.succeeded());
  EXPECT_EQ(end.signal, SIGUSR1);
  EXPECT_EQ(end.exit_status, -1);
  EXPECT_EQ(end.text().rfind("killed by signal " + std::to_string(SIGUSR1) + " (", 0), 0u) << end.text();
}

TEST(ChildProcess, MissingExecutableIsAStartErrorNamingIt) {
  ChildProcessSpec spec;
  spec.argv = {"/nonexistent/ppp_no_such_tool", "x"};
  try {
    ChildProcess::spawn(spec);
    FAIL() << "a missing executable started";
  } catch (const ProcessStartError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot start /nonexistent/ppp_no_such_tool: " + std::string(std::strerror(ENOENT)));
  }
  // Looked up on PATH: not found either.
  spec.argv = {"ppp_no_such_tool_on_path"};
  spec.search_path = true;
  EXPECT_THROW(runChildProcess(spec), ProcessStartError);
  // A name without a directory is not looked up on PATH unless asked.
  spec.argv = {"sh", "-c", "exit 0"};
  spec.search_path = false;
  EXPECT_THROW(runChildProcess(spec), ProcessStartError);
  spec.search_path = true;
  EXPECT_TRUE(runChildProcess(spec).succeeded());
}

TEST(ChildProcess, FileWithoutExecutePermissionIsAStartError) {
  const fs::path dir = test::tempDir("child_noexec");
  const fs::path script = dir / "script.sh";
  std::ofstream(script) << "#!/bin/sh\nexit 0\n";
  fs::permissions(script, fs::perms::owner_read | fs::perms::owner_write);
  ChildProcessSpec spec;
  spec.argv = {script.string()};
  try {
    runChildProcess(spec);
    FAIL() << "a file without any execute bit started";  // not even root runs one (execve(2): EACCES)
  } catch (const ProcessStartError& e) {
    EXPECT_NE(std::string(e.what()).find(script.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(std::strerror(EACCES)), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(ChildProcess, OutputGoesToFilesNullOrWithStdout) {
  const fs::path dir = test::tempDir("child_output");
  const std::string script = "echo out1; echo err1 1>&2; echo out2; echo err2 1>&2";
  // Standard output and error to separate files; an existing file is truncated.
  const fs::path out = dir / "out.txt", err = dir / "err.txt";
  std::ofstream(out) << "an older, longer content that must disappear\n";
  ChildProcessSpec spec = shell(script);
  spec.stdout_to = ChildStream::file(out.string());
  spec.stderr_to = ChildStream::file(err.string());
  ASSERT_TRUE(runChildProcess(spec).succeeded());
  EXPECT_EQ(test::readFileBytes(out.string()), "out1\nout2\n");
  EXPECT_EQ(test::readFileBytes(err.string()), "err1\nerr2\n");
  // Standard error with standard output (2>&1): one file, in the order written.
  const fs::path both = dir / "both.txt";
  spec.stdout_to = ChildStream::file(both.string());
  spec.stderr_to = ChildStream::withStdout();
  ASSERT_TRUE(runChildProcess(spec).succeeded());
  EXPECT_EQ(test::readFileBytes(both.string()), "out1\nerr1\nout2\nerr2\n");
  // Standard error dropped, standard output captured.
  spec.stderr_to = ChildStream::null();
  const CapturedOutput captured = runCapturingOutput(spec);
  EXPECT_TRUE(captured.end.succeeded());
  EXPECT_EQ(captured.output, "out1\nout2\n");
  fs::remove_all(dir);
}

TEST(ChildProcess, CapturedOutputIsExactBytesAndComesWithTheExitStatus) {
  // A NUL byte, no final newline, and more than one pipe buffer (64 KiB on Linux).
  const CapturedOutput small = runCapturingOutput(shell("printf 'a\\000b'; exit 4"));
  EXPECT_EQ(small.output, std::string("a\0b", 3));
  EXPECT_EQ(small.end.exit_status, 4);
  const CapturedOutput big = runCapturingOutput(shell("i=0; while [ $i -lt 20000 ]; do echo 0123456789; i=$((i+1)); done"));
  EXPECT_TRUE(big.end.succeeded());
  EXPECT_EQ(big.output.size(), 20000u * 11u);
}

TEST(ChildProcess, UnusableOutputFileOrWorkingDirectoryIsNamedAndNothingRuns) {
  const fs::path dir = test::tempDir("child_unusable");
  const fs::path marker = dir / "ran";
  ChildProcessSpec spec = shell("touch " + marker.string());
  spec.stdout_to = ChildStream::file((dir / "no_such_dir" / "log.txt").string());
  try {
    runChildProcess(spec);
    FAIL() << "started with an output file that cannot be opened";
  } catch (const ProcessStartError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot start /bin/sh: cannot open " + (dir / "no_such_dir" / "log.txt").string()),
              std::string::npos)
        << e.what();
  }
  spec.stdout_to = ChildStream::inherit();
  spec.working_dir = (dir / "no_such_dir").string();
  try {
    runChildProcess(spec);
    FAIL() << "started in a working directory that does not exist";
  } catch (const ProcessStartError& e) {
    EXPECT_NE(std::string(e.what()).find("working directory " + spec.working_dir), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(marker));
  fs::remove_all(dir);
}

TEST(ChildProcess, EnvironmentAndWorkingDirectory) {
  const fs::path dir = fs::canonical(test::tempDir("child_env"));
  ::setenv("PPP_CHILD_TEST_KEPT", "kept", 1);
  ::setenv("PPP_CHILD_TEST_SET", "parent", 1);
  ChildProcessSpec spec = shell("printf '%s|%s|%s|' \"$PPP_CHILD_TEST_KEPT\" \"$PPP_CHILD_TEST_SET\" \"$PPP_CHILD_TEST_NEW\"; pwd -P");
  spec.environment = {{"PPP_CHILD_TEST_SET", "child"}, {"PPP_CHILD_TEST_NEW", "new value"}};
  spec.working_dir = dir.string();
  const CapturedOutput run = runCapturingOutput(spec);
  EXPECT_EQ(run.output, "kept|child|new value|" + dir.string() + "\n");
  // The parent's own environment is not changed.
  EXPECT_STREQ(std::getenv("PPP_CHILD_TEST_SET"), "parent");
  EXPECT_EQ(std::getenv("PPP_CHILD_TEST_NEW"), nullptr);
  ::unsetenv("PPP_CHILD_TEST_KEPT");
  ::unsetenv("PPP_CHILD_TEST_SET");
  fs::remove_all(dir);
}

TEST(ChildProcess, RunningChildIsKilled) {
  const auto t0 = Clock::now();
  ChildProcess child = ChildProcess::spawn(shell("exec sleep 30"));
  EXPECT_FALSE(child.poll().has_value());  // still running
  EXPECT_FALSE(child.end().has_value());
  child.kill(SIGTERM);
  const ProcessEnd end = child.wait();
  EXPECT_EQ(end.signal, SIGTERM);
  EXPECT_LT(secondsSince(t0), 10.0);  // not the 30 s of the sleep
  ASSERT_TRUE(child.end().has_value());
  EXPECT_EQ(child.poll()->signal, SIGTERM);  // collected once; the end stays
  child.kill(SIGKILL);  // collected: nothing is sent
  EXPECT_FALSE(processExists(child.pid()));
}

TEST(ChildProcess, DroppedRunningChildIsKilledAndCollected) {
  const auto t0 = Clock::now();
  pid_t pid = -1;
  {
    ChildProcess child = ChildProcess::spawn(shell("exec sleep 30"));
    pid = child.pid();
    ASSERT_TRUE(processExists(pid));
    ChildProcess moved = std::move(child);  // the new owner drops it
    EXPECT_EQ(moved.pid(), pid);
  }
  EXPECT_FALSE(processExists(pid));  // killed and collected (no zombie)
  EXPECT_LT(secondsSince(t0), 10.0);
}

TEST(ChildProcess, WaitForAnyChildFindsTheOneThatEnded) {
  ChildProcess slow = ChildProcess::spawn(shell("exec sleep 30"));
  ChildProcess quick = ChildProcess::spawn(shell("exit 7"));
  EXPECT_EQ(waitForAnyChildToEnd(), quick.pid());
  EXPECT_FALSE(slow.poll().has_value());
  EXPECT_EQ(quick.wait().exit_status, 7);  // not collected by the wait for any
  slow.kill(SIGKILL);
  EXPECT_EQ(waitForAnyChildToEnd(), slow.pid());
  EXPECT_EQ(slow.wait().signal, SIGKILL);
  EXPECT_EQ(waitForAnyChildToEnd(), -1);  // no child left
}
