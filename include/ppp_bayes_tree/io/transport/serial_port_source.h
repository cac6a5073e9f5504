#pragma once
// SerialPortSource: a serial device (/dev/ttyACM0, /dev/ttyUSB0, a pty) read
// in raw mode, 8 data bits, no parity, 1 stop bit, no flow control, at a
// standard baud rate 9600..921600 (termios(3); POSIX.1-2017 "General Terminal
// Interface"). Opened on the first read(); a device that disappears (USB
// unplugged) gives ReadFailed or Closed, which ReconnectingByteSource retries.
#include <string>

#include "ppp_bayes_tree/io/transport/byte_source.h"

namespace ppp {

/// True when `baud` is one of 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600.
bool isSupportedBaudRate(int baud);

class SerialPortSource : public ByteSource {
 public:
  SerialPortSource(std::string device, int baud);
  ~SerialPortSource() override;
  SerialPortSource(const SerialPortSource&) = delete;
  SerialPortSource& operator=(const SerialPortSource&) = delete;

  ByteSourceRead read(std::uint8_t* buffer, std::size_t capacity,
                      std::chrono::milliseconds timeout) override;
  std::string describe() const override;
  void close() override;

 private:
  std::optional<ByteSourceError> open();

  std::string device_;
  int baud_;
  int fd_ = -1;
};

}  // namespace ppp
