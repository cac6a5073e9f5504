#include "ppp_bayes_tree/io/transport/serial_port_source.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ppp {
namespace {

std::optional<speed_t> baudConstant(int baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    default: return std::nullopt;
  }
}

}  // namespace

bool isSupportedBaudRate(int baud) { return baudConstant(baud).has_value(); }

SerialPortSource::SerialPortSource(std::string device, int baud) : device_(std::move(device)), baud_(baud) {}

SerialPortSource::~SerialPortSource() { close(); }

std::string SerialPortSource::describe() const {
  return "serial://" + device_ + "?baud=" + std::to_string(baud_);
}

void SerialPortSource::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

std::optional<ByteSourceError> SerialPortSource::open() {
  const auto speed = baudConstant(baud_);
  if (!speed) {
    return ByteSourceError{ByteSourceErrorKind::BadSpec,
                           device_ + ": baud rate " + std::to_string(baud_) +
                               " is not one of 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600"};
  }
  const int fd = ::open(device_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    return ByteSourceError{ByteSourceErrorKind::OpenFailed, device_ + ": " + std::strerror(errno)};
  }
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    return ByteSourceError{ByteSourceErrorKind::OpenFailed, device_ + " is not a terminal device: " + why};
  }
  ::cfmakeraw(&tio);  // no echo, no line editing, no character translation, 8 bits
  tio.c_cflag &= ~static_cast<tcflag_t>(PARENB | CSTOPB | CSIZE | CRTSCTS);
  tio.c_cflag |= CS8 | CLOCAL | CREAD;
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  ::cfsetispeed(&tio, *speed);
  ::cfsetospeed(&tio, *speed);
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    return ByteSourceError{ByteSourceErrorKind::OpenFailed, device_ + ": cannot set 8N1 raw at " +
                                                                std::to_string(baud_) + " baud: " + why};
  }
  fd_ = fd;
  return std::nullopt;
}

ByteSourceRead SerialPortSource::read(std::uint8_t* buffer, std::size_t capacity,
                                      std::chrono::milliseconds timeout) {
  if (fd_ < 0) {
    if (auto error = open()) return fail(error->kind, std::move(error->detail));
    ++counters_.connects;
  }
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, static_cast<int>(std::max<long long>(0, timeout.count())));
  if (ready < 0) {
    if (errno == EINTR) return ByteSourceRead::timeout();
    const std::string why = std::strerror(errno);
    close();
    return fail(ByteSourceErrorKind::ReadFailed, device_ + ": poll: " + why);
  }
  if (ready == 0) return ByteSourceRead::timeout();
  const ssize_t n = ::read(fd_, buffer, capacity);
  if (n > 0) {
    counters_.bytes += static_cast<std::uint64_t>(n);
    return ByteSourceRead::data(static_cast<std::size_t>(n));
  }
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return ByteSourceRead::timeout();
  // POLLHUP with no data (the other end of a pty closed, a USB device unplugged).
  const std::string why = n == 0 ? std::string("hang-up (device closed or unplugged)") : std::strerror(errno);
  close();
  return fail(ByteSourceErrorKind::ConnectionLost, device_ + ": " + why);
}

}  // namespace ppp
