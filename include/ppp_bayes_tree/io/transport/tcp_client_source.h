#pragma once
// TcpClientSource: bytes from a TCP server (a receiver's or str2str's tcpsvr
// port). Connects on the first read() with a connect timeout (non-blocking
// connect + poll); a connection that delivers no byte for the stall timeout is
// dropped as Stalled (counted), so that ReconnectingByteSource reconnects.
// TcpConnection is the socket part, shared with the NTRIP client.
#include <chrono>
#include <optional>
#include <string>

#include "ppp_bayes_tree/io/transport/byte_source.h"

namespace ppp {

/// One connected TCP socket (closed on destruction).
class TcpConnection {
 public:
  TcpConnection() = default;
  ~TcpConnection();
  TcpConnection(const TcpConnection&) = delete;
  TcpConnection& operator=(const TcpConnection&) = delete;

  /// Connects; on failure the error (HostNotFound, ConnectionRefused, ConnectTimeout, ...).
  std::optional<ByteSourceError> connect(const std::string& host, int port,
                                         std::chrono::milliseconds timeout);
  bool isOpen() const { return fd_ >= 0; }
  void close();
  /// Sends all bytes (WriteFailed on error).
  std::optional<ByteSourceError> sendAll(const std::string& bytes);
  /// Status Data (size > 0), Timeout, Closed (peer closed) or Error (ReadFailed).
  ByteSourceRead receive(std::uint8_t* buffer, std::size_t capacity,
                         std::chrono::milliseconds timeout);

 private:
  int fd_ = -1;
};

class TcpClientSource : public ByteSource {
 public:
  TcpClientSource(std::string host, int port, std::chrono::milliseconds connect_timeout,
                  std::chrono::milliseconds stall_timeout);

  ByteSourceRead read(std::uint8_t* buffer, std::size_t capacity,
                      std::chrono::milliseconds timeout) override;
  std::string describe() const override;
  void close() override;

 private:
  std::string host_;
  int port_;
  std::chrono::milliseconds connect_timeout_;
  std::chrono::milliseconds stall_timeout_;
  TcpConnection connection_;
  std::chrono::steady_clock::time_point last_byte_time_;
};

}  // namespace ppp
