#pragma once
// Real loopback peers for the ByteSource tests: RTKLIB's str2str run as a child
// process (an NTRIP caster or a TCP server fed through its stdin), and a tiny
// scripted TCP server on a thread (a caster answering in NTRIP v2 with chunked
// transfer, a 404, or a server that accepts and then stalls).
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace ppp::test {

/// A TCP port that was free a moment ago on 127.0.0.1.
inline int freeLoopbackPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a));
  socklen_t len = sizeof(a);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

inline bool str2strAvailable() { return std::system("str2str -h > /dev/null 2>&1") == 0 || std::system("command -v str2str > /dev/null 2>&1") == 0; }

/// str2str with its stdin as the input stream and one output (e.g.
/// "ntripc://user:pass@:PORT/MNT" or "tcpsvr://:PORT"); killed on destruction.
class Str2str {
 public:
  explicit Str2str(const std::string& output) {
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fds[0], 0);
      ::close(fds[0]);
      ::close(fds[1]);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 1);
      ::dup2(null, 2);
      ::execlp("str2str", "str2str", "-out", output.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[0]);
    stdin_ = fds[1];
  }
  ~Str2str() { stop(); }
  Str2str(const Str2str&) = delete;
  Str2str& operator=(const Str2str&) = delete;

  bool running() const { return pid_ > 0; }
  /// Writes bytes to str2str's input, 8 KiB every 20 ms (400 KiB/s): str2str
  /// drops output that does not fit its socket buffers, as a live server does.
  bool write(const std::string& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(stdin_, bytes.data() + done, std::min<std::size_t>(8192, bytes.size() - done));
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }
  /// Ends str2str's input (it reads its stdin in fixed blocks with fread(3): the
  /// last partial block is passed on only at end of input).
  void closeInput() {
    if (stdin_ >= 0) ::close(stdin_);
    stdin_ = -1;
  }
  void stop() {
    closeInput();
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
  int stdin_ = -1;
};

/// Listens on 127.0.0.1:port; for each accepted connection runs `serve(fd)`
/// on its own thread (the request is not read for it). Stops on destruction.
class ScriptedServer {
 public:
  using Serve = std::function<void(int fd, const std::atomic<bool>& stop)>;
  explicit ScriptedServer(Serve serve) : serve_(std::move(serve)) {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a));
    socklen_t len = sizeof(a);
    ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    ::listen(listen_fd_, 8);
    thread_ = std::thread([this] {
      while (!stop_) {
        pollfd p{listen_fd_, POLLIN, 0};
        if (::poll(&p, 1, 50) <= 0) continue;
        const int fd = ::accept(listen_fd_, nullptr, nullptr);
        if (fd < 0) continue;
        ++accepted_;
        connections_.emplace_back([this, fd] {
          serve_(fd, stop_);
          ::close(fd);
        });
      }
    });
  }
  ~ScriptedServer() {
    stop_ = true;
    thread_.join();
    for (auto& t : connections_) t.join();
    ::close(listen_fd_);
  }
  int port() const { return port_; }
  int accepted() const { return accepted_; }

  /// Reads the request up to its blank line (at most 2 s); the text.
  static std::string readRequest(int fd) {
    std::string text;
    char c;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (text.find("\r\n\r\n") == std::string::npos && std::chrono::steady_clock::now() < until) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      if (::recv(fd, &c, 1, 0) != 1) break;
      text += c;
    }
    return text;
  }
  static void sendAll(int fd, const std::string& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
      if (n <= 0) return;
      done += static_cast<std::size_t>(n);
    }
  }

 private:
  Serve serve_;
  int listen_fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> accepted_{0};
  std::thread thread_;
  std::vector<std::thread> connections_;  // one per accepted connection
};

}  // namespace ppp::test
