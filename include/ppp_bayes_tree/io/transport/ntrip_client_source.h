#pragma once
// NtripClientSource: the data of one mountpoint from an NTRIP caster.
//
// NTRIP v1 (RTCM 10410.0, "Networked Transport of RTCM via Internet Protocol",
// version 1.0, appendix B): "GET /MOUNT HTTP/1.0" with User-Agent "NTRIP ..."
// and Basic authorization (RFC 7617); the caster answers "ICY 200 OK" and then
// sends the raw stream, or "SOURCETABLE 200 OK" with its source table when the
// mountpoint is unknown, or "HTTP/1.x 401 Unauthorized".
// NTRIP v2 (RTCM 10410.1, version 2.0): "GET /MOUNT HTTP/1.1" with Host and
// "Ntrip-Version: Ntrip/2.0"; the answer is "HTTP/1.1 200 OK", usually with
// "Transfer-Encoding: chunked" (RFC 7230 section 4.1), which is decoded here;
// unknown mountpoints get 404 (or the source table). Casters that answer a v2
// request in v1 style ("ICY 200 OK", as RTKLIB's str2str does) are accepted.
//
// An optional GGA sentence (io/transport/nmea_gga.h) is sent after the request and then
// every gga_period, for network mountpoints that need the user's position.
// No byte for the stall timeout drops the connection (Stalled, counted).
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/transport/byte_source.h"
#include "ppp_bayes_tree/io/transport/tcp_client_source.h"

namespace ppp {

struct NtripClientOptions {
  std::string host;
  int port = 2101;
  std::string mountpoint;
  std::string user;
  std::string password;  // never printed
  int version = 2;       // 1 or 2
  std::chrono::milliseconds connect_timeout{5000};
  std::chrono::milliseconds stall_timeout{10000};
  std::optional<std::chrono::milliseconds> gga_period;  // send GGA upstream when set
  double gga_latitude_deg = 0.0;
  double gga_longitude_deg = 0.0;
  double gga_height_m = 0.0;
};

class NtripClientSource : public ByteSource {
 public:
  explicit NtripClientSource(NtripClientOptions options);

  ByteSourceRead read(std::uint8_t* buffer, std::size_t capacity,
                      std::chrono::milliseconds timeout) override;
  std::string describe() const override;
  void close() override;

  /// "ICY 200 OK" / "HTTP/1.1 200 OK" of the current connection ("" before).
  const std::string& statusLine() const { return status_line_; }
  /// The current (or last) answer uses chunked transfer encoding.
  bool chunked() const { return chunked_; }

 private:
  std::optional<ByteSourceError> openStream(std::chrono::steady_clock::time_point deadline);
  std::optional<ByteSourceError> sendGgaIfDue();
  /// Moves payload bytes out of raw_ (de-chunking when needed) into `buffer`.
  std::size_t takePayload(std::uint8_t* buffer, std::size_t capacity,
                          std::optional<ByteSourceError>& error);

  NtripClientOptions options_;
  TcpConnection connection_;
  bool streaming_ = false;
  bool chunked_ = false;
  std::string status_line_;
  std::vector<std::uint8_t> raw_;         // received, not yet delivered
  std::optional<std::size_t> chunk_left_; // bytes left in the current chunk (chunked)
  bool stream_ended_ = false;             // the last (zero) chunk was seen
  std::chrono::steady_clock::time_point last_byte_time_;
  std::chrono::steady_clock::time_point next_gga_time_;
};

/// "Basic dXNlcjpwYXNz" for RFC 7617 Basic authorization.
std::string basicAuthorization(const std::string& user, const std::string& password);

}  // namespace ppp
