#include "ppp_bayes_tree/io/transport/tcp_client_source.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ppp {
namespace {

std::string endpoint(const std::string& host, int port) { return host + ":" + std::to_string(port); }

int pollMs(std::chrono::milliseconds timeout) {
  return timeout.count() < 0 ? 0 : static_cast<int>(std::min<long long>(timeout.count(), 1 << 30));
}

}  // namespace

TcpConnection::~TcpConnection() { close(); }

void TcpConnection::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

std::optional<ByteSourceError> TcpConnection::connect(const std::string& host, int port,
                                                      std::chrono::milliseconds timeout) {
  close();
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* list = nullptr;
  const std::string service = std::to_string(port);
  const int rc = ::getaddrinfo(host.c_str(), service.c_str(), &hints, &list);
  if (rc != 0 || list == nullptr) {
    return ByteSourceError{ByteSourceErrorKind::HostNotFound,
                           "'" + host + "': " + ::gai_strerror(rc)};
  }
  std::optional<ByteSourceError> error;
  for (addrinfo* a = list; a != nullptr; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      error = ByteSourceError{ByteSourceErrorKind::OpenFailed, std::string("socket: ") + std::strerror(errno)};
      continue;
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    int result = ::connect(fd, a->ai_addr, a->ai_addrlen);
    int err = result == 0 ? 0 : errno;
    if (result != 0 && err == EINPROGRESS) {
      pollfd p{fd, POLLOUT, 0};
      const int ready = ::poll(&p, 1, pollMs(timeout));
      if (ready == 0) {
        ::close(fd);
        error = ByteSourceError{ByteSourceErrorKind::ConnectTimeout,
                                endpoint(host, port) + ": no connection within " +
                                    std::to_string(timeout.count()) + " ms"};
        continue;
      }
      socklen_t len = sizeof(err);
      ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
    }
    if (err != 0) {
      ::close(fd);
      error = ByteSourceError{err == ECONNREFUSED ? ByteSourceErrorKind::ConnectionRefused
                                                  : ByteSourceErrorKind::OpenFailed,
                              endpoint(host, port) + ": " + std::strerror(err)};
      continue;
    }
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    fd_ = fd;
    error.reset();
    break;
  }
  ::freeaddrinfo(list);
  return error;
}

std::optional<ByteSourceError> TcpConnection::sendAll(const std::string& bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, 5000) <= 0) {
        return ByteSourceError{ByteSourceErrorKind::WriteFailed, "send: socket not writable for 5 s"};
      }
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return ByteSourceError{ByteSourceErrorKind::WriteFailed, std::string("send: ") + std::strerror(errno)};
    sent += static_cast<std::size_t>(n);
  }
  return std::nullopt;
}

ByteSourceRead TcpConnection::receive(std::uint8_t* buffer, std::size_t capacity,
                                      std::chrono::milliseconds timeout) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, pollMs(timeout));
  if (ready < 0) {
    if (errno == EINTR) return ByteSourceRead::timeout();
    return ByteSourceRead::failure(ByteSourceErrorKind::ReadFailed, std::string("poll: ") + std::strerror(errno));
  }
  if (ready == 0) return ByteSourceRead::timeout();
  const ssize_t n = ::recv(fd_, buffer, capacity, 0);
  if (n > 0) return ByteSourceRead::data(static_cast<std::size_t>(n));
  if (n == 0) return ByteSourceRead::closed();
  if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return ByteSourceRead::timeout();
  if (errno == ECONNRESET) {
    return ByteSourceRead::failure(ByteSourceErrorKind::ConnectionLost, "connection reset by peer");
  }
  return ByteSourceRead::failure(ByteSourceErrorKind::ReadFailed, std::string("recv: ") + std::strerror(errno));
}

TcpClientSource::TcpClientSource(std::string host, int port, std::chrono::milliseconds connect_timeout,
                                 std::chrono::milliseconds stall_timeout)
    : host_(std::move(host)), port_(port), connect_timeout_(connect_timeout), stall_timeout_(stall_timeout) {}

std::string TcpClientSource::describe() const { return "tcp://" + endpoint(host_, port_); }

void TcpClientSource::close() { connection_.close(); }

ByteSourceRead TcpClientSource::read(std::uint8_t* buffer, std::size_t capacity,
                                     std::chrono::milliseconds timeout) {
  using Clock = std::chrono::steady_clock;
  if (!connection_.isOpen()) {
    if (auto error = connection_.connect(host_, port_, connect_timeout_)) {
      return fail(error->kind, std::move(error->detail));
    }
    ++counters_.connects;
    last_byte_time_ = Clock::now();
  }
  const auto now = Clock::now();
  const auto stall_left =
      std::chrono::duration_cast<std::chrono::milliseconds>(last_byte_time_ + stall_timeout_ - now);
  ByteSourceRead result = connection_.receive(buffer, capacity, std::min(timeout, std::max(stall_left, std::chrono::milliseconds(0))));
  if (result.status == ByteSourceStatus::Data) {
    counters_.bytes += result.size;
    last_byte_time_ = Clock::now();
    return result;
  }
  if (result.status == ByteSourceStatus::Timeout) {
    if (Clock::now() - last_byte_time_ >= stall_timeout_) {
      connection_.close();
      return fail(ByteSourceErrorKind::Stalled,
                  describe() + ": no byte for " + std::to_string(stall_timeout_.count() / 1000.0).substr(0, 5) + " s");
    }
    return result;
  }
  connection_.close();
  if (result.status == ByteSourceStatus::Closed) {
    return fail(ByteSourceErrorKind::ConnectionLost, describe() + ": the server closed the connection");
  }
  counters_.addError(*result.error);
  return result;
}

}  // namespace ppp
