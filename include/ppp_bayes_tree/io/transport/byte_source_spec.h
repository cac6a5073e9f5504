#pragma once
// ByteSourceSpec: one string that names a live or replayed input, for users,
// launch files and ppp_stream_record. Syntax (URI-like; options after '?',
// joined by '&'; user and password may be percent-encoded):
//
//   serial:///dev/ttyACM0?baud=115200
//   tcp://host:port
//   ntrip://user:password@host:port/MOUNT?version=2&gga_period_s=10&lat=55.5&lon=8.4&h=50
//   file:///path/x.rtcm3?speed=1
//
// Options (every kind):   format=rtcm3|ubx (default: from the content; files and
//                         ppp_stream_node use it), reconnect_min_s=1, reconnect_max_s=60
// serial:                 baud (9600..921600, default 115200); always 8N1, raw.
// tcp, ntrip:             connect_timeout_s=5, stall_timeout_s=10 (no byte for this
//                         long: the connection is dropped and counted as a stall)
// ntrip:                  port default 2101; version=1|2 (default 2);
//                         credentials=PATH: user and password from a file readable by
//                         its owner only (io/transport/ntrip_credentials.h; also the variable
//                         PPP_NTRIP_CREDENTIALS), so that the spec carries no password;
//                         gga_period_s (> 0: send GGA upstream at this period, needs
//                         lat [deg], lon [deg], h [m, ellipsoidal]).
// file:                   speed=1 (real time x factor; 0 = as fast as read),
//                         byte_rate=11520 [bytes/s at speed 1] for recordings whose
//                         frames carry no epoch time.
//
// parseByteSourceSpec throws ByteSourceSpecError with a message naming the
// offending part. describe(), every error and every log line omit the password
// (io/transport/credential_mask.h maskCredentials, robust to mistyped specs).
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/io/transport/byte_source.h"

namespace ppp {

class ByteSourceSpecError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ByteSourceKind { Serial, Tcp, Ntrip, File };

struct ByteSourceSpec {
  ByteSourceKind kind = ByteSourceKind::File;
  std::string text_without_password;  // the spec as given, password replaced by "***"

  std::optional<std::string> format;  // "rtcm3" or "ubx" when given

  // serial
  std::string device;
  int baud = 115200;

  // tcp, ntrip
  std::string host;
  int port = 0;
  double connect_timeout_s = 5.0;
  double stall_timeout_s = 10.0;

  // ntrip
  std::string mountpoint;
  std::string user;
  std::string password;
  std::string credentials_file;  // credentials=PATH (io/transport/ntrip_credentials.h); read by resolveNtripCredentials
  int ntrip_version = 2;
  std::optional<double> gga_period_s;
  std::optional<double> gga_latitude_deg;
  std::optional<double> gga_longitude_deg;
  std::optional<double> gga_height_m;

  // file
  std::string path;
  double speed = 1.0;
  double byte_rate_bytes_per_s = 11520.0;

  // reconnection (serial, tcp, ntrip)
  double reconnect_min_s = 1.0;
  double reconnect_max_s = 60.0;
};

ByteSourceSpec parseByteSourceSpec(const std::string& text);

/// The source named by `spec`: serial, tcp and ntrip wrapped in a
/// ReconnectingByteSource; a file replay as is (it ends).
std::unique_ptr<ByteSource> openByteSource(const ByteSourceSpec& spec);
/// The source without the reconnecting wrapper (one connection attempt).
std::unique_ptr<ByteSource> openSingleByteSource(const ByteSourceSpec& spec);

}  // namespace ppp
