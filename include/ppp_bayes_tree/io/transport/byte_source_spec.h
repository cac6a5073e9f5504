#pragma once
// ByteSourceSpec: one string that names a live or replayed input, for users,
// launch files and ppp_stream_record: serial:///dev/ttyACM0?baud=115200,
// tcp://host:port, ntrip://user:password@host:port/MOUNT?version=2,
// file:///path/x.rtcm3?speed=1, with options after '?'. parseByteSourceSpec
// throws ByteSourceSpecError naming the offending part. describe(), every error
// and every log line omit the password (io/transport/credential_mask.h).
// Every kind's options and defaults: doc/live_input.md, "Input spec options".
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
