#include "ppp_bayes_tree/app/child_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

extern char** environ;

namespace ppp {
namespace {

/// File descriptors opened for one start, closed when it is over (the child has its copies).
class StartDescriptors {
 public:
  ~StartDescriptors() {
    for (int fd : fds_)
      if (fd >= 0) ::close(fd);
  }
  int keep(int fd) {
    fds_.push_back(fd);
    return fd;
  }
  /// Forgets `fd` without closing it (it outlives the start).
  void release(int fd) {
    for (auto& f : fds_)
      if (f == fd) f = -1;
  }

 private:
  std::vector<int> fds_;
};

/// posix_spawn's settings, destroyed with this object.
class SpawnActions {
 public:
  SpawnActions() { posix_spawn_file_actions_init(&actions_); }
  ~SpawnActions() { posix_spawn_file_actions_destroy(&actions_); }
  SpawnActions(const SpawnActions&) = delete;
  SpawnActions& operator=(const SpawnActions&) = delete;
  posix_spawn_file_actions_t* get() { return &actions_; }

 private:
  posix_spawn_file_actions_t actions_;
};

std::string systemError(int error) { return std::strerror(error); }

/// A descriptor above the standard ones (dup2 onto 0-2 must not find it there), close-on-exec.
int aboveStandardStreams(int fd) {
  if (fd < 0 || fd > STDERR_FILENO) return fd;
  const int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
  const int error = errno;
  ::close(fd);
  errno = error;
  return moved;
}

/// The child's environment: this process's with `overrides` set.
std::vector<std::string> childEnvironment(const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::vector<std::string> env;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    const std::string entry = *e;
    const std::string name = entry.substr(0, entry.find('='));
    bool replaced = false;
    for (const auto& [n, v] : overrides) replaced = replaced || n == name;
    if (!replaced) env.push_back(entry);
  }
  for (const auto& [name, value] : overrides) env.push_back(name + "=" + value);
  return env;
}

std::vector<char*> pointers(std::vector<std::string>& texts) {
  std::vector<char*> p;
  for (auto& t : texts) p.push_back(t.data());
  p.push_back(nullptr);
  return p;
}

/// Adds the redirection of `target` (STDOUT_FILENO / STDERR_FILENO) to `actions`;
/// returns the read end of a pipe for ChildStream::Pipe, else -1. Throws the
/// reason (without the executable) as std::runtime_error.
int redirect(const ChildStream& stream, int target, SpawnActions& actions, StartDescriptors& fds) {
  switch (stream.kind) {
    case ChildStream::Kind::Inherit: return -1;
    case ChildStream::Kind::WithStdout:
      if (target != STDERR_FILENO) throw std::runtime_error("only standard error can go with standard output");
      posix_spawn_file_actions_adddup2(actions.get(), STDOUT_FILENO, STDERR_FILENO);
      return -1;
    case ChildStream::Kind::File:
    case ChildStream::Kind::Null: {
      const std::string path = stream.kind == ChildStream::Kind::Null ? "/dev/null" : stream.path;
      const int fd = aboveStandardStreams(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
      if (fd < 0) throw std::runtime_error("cannot open " + path + " for writing: " + systemError(errno));
      posix_spawn_file_actions_adddup2(actions.get(), fds.keep(fd), target);
      return -1;
    }
    case ChildStream::Kind::Pipe: {
      if (target != STDOUT_FILENO) throw std::runtime_error("only standard output can go through a pipe");
      int ends[2];
      if (::pipe2(ends, O_CLOEXEC) != 0) throw std::runtime_error("cannot make a pipe: " + systemError(errno));
      fds.keep(ends[0]);
      const int write_end = aboveStandardStreams(ends[1]);
      if (write_end < 0) throw std::runtime_error("cannot make a pipe: " + systemError(errno));
      posix_spawn_file_actions_adddup2(actions.get(), fds.keep(write_end), target);
      return ends[0];
    }
  }
  return -1;
}

ProcessEnd endFromStatus(int status) {
  ProcessEnd end;
  if (WIFSIGNALED(status)) end.signal = WTERMSIG(status);
  else end.exit_status = WEXITSTATUS(status);
  return end;
}

}  // namespace

std::string ProcessEnd::text() const {
  if (exited()) return "exited with status " + std::to_string(exit_status);
  const char* description = ::strsignal(signal);
  return "killed by signal " + std::to_string(signal) + (description ? std::string(" (") + description + ")" : "");
}

ChildProcess ChildProcess::spawn(const ChildProcessSpec& spec) {
  const std::string name = spec.argv.empty() ? std::string("(no executable)") : spec.argv.front();
  auto fail = [&](const std::string& why) { return ProcessStartError("cannot start " + name + ": " + why); };
  if (spec.argv.empty() || spec.argv.front().empty()) throw fail("no executable named");
  std::error_code ec;
  if (!spec.working_dir.empty() && !std::filesystem::is_directory(spec.working_dir, ec))
    throw fail("working directory " + spec.working_dir + " does not exist");
  SpawnActions actions;
  StartDescriptors fds;
  int output_fd = -1;
  try {
    output_fd = redirect(spec.stdout_to, STDOUT_FILENO, actions, fds);
    redirect(spec.stderr_to, STDERR_FILENO, actions, fds);
  } catch (const std::runtime_error& e) {
    throw fail(e.what());
  }
  if (!spec.working_dir.empty()) posix_spawn_file_actions_addchdir_np(actions.get(), spec.working_dir.c_str());
  std::vector<std::string> args = spec.argv, env = childEnvironment(spec.environment);
  std::vector<char*> argv = pointers(args), envp = pointers(env);
  pid_t pid = -1;
  const int rc = spec.search_path ? posix_spawnp(&pid, argv[0], actions.get(), nullptr, argv.data(), envp.data())
                                  : posix_spawn(&pid, argv[0], actions.get(), nullptr, argv.data(), envp.data());
  if (rc != 0) throw fail(systemError(rc));
  fds.release(output_fd);  // the pipe's read end is the parent's; the rest closes here
  return ChildProcess(pid, output_fd);
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)),
      output_fd_(std::exchange(other.output_fd_, -1)),
      end_(std::move(other.end_)) {}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
  if (this != &other) {
    release();
    pid_ = std::exchange(other.pid_, -1);
    output_fd_ = std::exchange(other.output_fd_, -1);
    end_ = std::move(other.end_);
  }
  return *this;
}

ChildProcess::~ChildProcess() { release(); }

void ChildProcess::release() {
  if (output_fd_ >= 0) ::close(output_fd_);
  output_fd_ = -1;
  if (pid_ > 0 && !end_) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  pid_ = -1;
}

std::optional<ProcessEnd> ChildProcess::poll() {
  if (end_ || pid_ <= 0) return end_;
  int status = 0;
  pid_t got;
  while ((got = ::waitpid(pid_, &status, WNOHANG)) < 0 && errno == EINTR) {
  }
  if (got == pid_) end_ = endFromStatus(status);
  return end_;
}

ProcessEnd ChildProcess::wait() {
  if (end_ || pid_ <= 0) return end_.value_or(ProcessEnd{});
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0) {
    if (errno == EINTR) continue;
    // Collected elsewhere (a waitpid(-1) of other code): its status is lost.
    end_ = ProcessEnd{};
    return *end_;
  }
  end_ = endFromStatus(status);
  return *end_;
}

void ChildProcess::kill(int signal) {
  if (pid_ > 0 && !end_) ::kill(pid_, signal);
}

std::string ChildProcess::readOutput() {
  std::string out;
  if (output_fd_ < 0) return out;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(output_fd_, buf, sizeof buf);
    if (n > 0) out.append(buf, static_cast<std::size_t>(n));
    else if (n == 0 || errno != EINTR) break;
  }
  ::close(output_fd_);
  output_fd_ = -1;
  return out;
}

pid_t waitForAnyChildToEnd() {
  siginfo_t info{};
  for (;;) {
    info.si_pid = 0;
    if (::waitid(P_ALL, 0, &info, WEXITED | WNOWAIT) == 0) return info.si_pid;
    if (errno != EINTR) return -1;
  }
}

ProcessEnd runChildProcess(const ChildProcessSpec& spec) { return ChildProcess::spawn(spec).wait(); }

CapturedOutput runCapturingOutput(ChildProcessSpec spec) {
  spec.stdout_to = ChildStream::pipe();
  ChildProcess child = ChildProcess::spawn(spec);
  CapturedOutput out;
  out.output = child.readOutput();
  out.end = child.wait();
  return out;
}

}  // namespace ppp
