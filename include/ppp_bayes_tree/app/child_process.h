#pragma once
// Child processes of the batch tools: the one way ppp_campaign starts a process
// (the local pool's `ppp_campaign run-job DIR`, a bag job's ppp_bag_solve, the
// Slurm commands sbatch / squeue / sacct / scontrol, the summary plot).
//
// A child is started with posix_spawn (POSIX.1-2008) from a specification: its
// arguments, variables set over this process's environment, a working directory,
// and where its standard output and error go (this process's, a file, /dev/null,
// the error with the output, or the output through a pipe read by this process).
// Files are opened by this process before the child starts, so a file that cannot
// be written is reported by name; an executable that is missing or cannot run is
// reported by the start itself (ProcessStartError): no child runs in either case.
// The child inherits this process's signal dispositions and mask (so a campaign
// started under nohup keeps its jobs immune to hangups) and its standard input.
//
// How a child ended (ProcessEnd): its exit status, or the signal that killed it.
// A ChildProcess that is dropped while its child still runs kills the child
// (SIGKILL) and collects it: no child outlives its owner unseen, none is left a zombie.
#include <sys/types.h>

#include <csignal>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ppp {

/// Where a child's standard output or standard error goes.
struct ChildStream {
  enum class Kind {
    Inherit,       // this process's stream
    File,          // `path`, created or truncated (mode 0644)
    Null,          // /dev/null
    WithStdout,    // standard error only: wherever standard output goes (2>&1)
    Pipe,          // standard output only: read by ChildProcess::readOutput
  };
  Kind kind = Kind::Inherit;
  std::string path;  // File

  static ChildStream inherit() { return {}; }
  static ChildStream file(std::string path) { return {Kind::File, std::move(path)}; }
  static ChildStream null() { return {Kind::Null, {}}; }
  static ChildStream withStdout() { return {Kind::WithStdout, {}}; }
  static ChildStream pipe() { return {Kind::Pipe, {}}; }
};

/// What a child process is started with.
struct ChildProcessSpec {
  /// argv[0] is the executable: a path (relative ones from `working_dir` when
  /// set), or with `search_path` a name looked up on PATH like a shell does.
  std::vector<std::string> argv;
  bool search_path = false;
  /// Variables set in the child over this process's environment (NAME, value).
  std::vector<std::pair<std::string, std::string>> environment;
  /// The child's working directory; empty: this process's.
  std::string working_dir;
  ChildStream stdout_to, stderr_to;
};

/// How a child ended: exited with a status, or killed by a signal.
struct ProcessEnd {
  int exit_status = -1;  // the status it exited with; -1 when a signal killed it
  int signal = 0;        // the signal that killed it; 0 when it exited
  bool exited() const { return signal == 0; }
  bool succeeded() const { return signal == 0 && exit_status == 0; }
  /// "exited with status 3", "killed by signal 9 (Killed)".
  std::string text() const;
};

/// A child that could not be started: "cannot start EXE: REASON" (the
/// executable missing or not executable, an output file or the working
/// directory unusable, no process left).
class ProcessStartError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One started child process, owned: movable, not copyable.
class ChildProcess {
 public:
  /// Starts a child; throws ProcessStartError when it cannot (no child then runs).
  static ChildProcess spawn(const ChildProcessSpec& spec);

  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&& other) noexcept;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  /// Kills (SIGKILL) and collects a child that has not been waited for.
  ~ChildProcess();

  pid_t pid() const { return pid_; }
  /// How it ended once collected (by wait or poll); nullopt while it runs.
  const std::optional<ProcessEnd>& end() const { return end_; }

  /// Collects the child when it has ended, without blocking; nullopt while it runs.
  std::optional<ProcessEnd> poll();
  /// Blocks until the child ends and collects it.
  ProcessEnd wait();
  /// Sends `signal` to the child while it has not been collected (afterwards its
  /// process id may belong to another process: nothing is sent).
  void kill(int signal = SIGTERM);
  /// Standard output started as ChildStream::pipe(): everything the child writes
  /// until it closes it (usually when it ends). Empty for other outputs.
  std::string readOutput();

 private:
  ChildProcess(pid_t pid, int output_fd) : pid_(pid), output_fd_(output_fd) {}
  void release();

  pid_t pid_ = -1;
  int output_fd_ = -1;  // the read end of the output pipe
  std::optional<ProcessEnd> end_;
};

/// Blocks until some child of this process has ended, without collecting it
/// (its ChildProcess::wait() then returns at once); returns its process id, or
/// -1 when this process has no child. For a pool that owns every child of the
/// process: the ended child may be one that a ChildProcess does not own.
pid_t waitForAnyChildToEnd();

/// Starts a child and waits for it to end. Throws ProcessStartError.
ProcessEnd runChildProcess(const ChildProcessSpec& spec);

/// A command's standard output and how it ended.
struct CapturedOutput {
  ProcessEnd end;
  std::string output;
};
/// Starts a child with its standard output through a pipe (spec.stdout_to is
/// replaced), reads all of it, then waits. Throws ProcessStartError.
CapturedOutput runCapturingOutput(ChildProcessSpec spec);

}  // namespace ppp
