#pragma once
// ByteSource: a live or replayed stream of receiver/correction bytes (serial
// port, TCP client, NTRIP client, file replay). read() returns what is
// available within a timeout, or says why not: a timeout (nothing yet), the
// stream closed (end of file, peer closed), or an error with a reason kind and
// a text for people. Sources open lazily on the first read(), so that opening
// errors arrive the same way as reading errors. describe() names the source
// for logs and never contains a password. POSIX only (poll/read/termios).
//
// Counters are per source; ReconnectingByteSource (io/transport/reconnecting_byte_source.h)
// sums them over its reconnections.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace ppp {

enum class ByteSourceErrorKind {
  BadSpec,                // the input spec or an option is invalid
  OpenFailed,             // a device or file could not be opened or configured
  HostNotFound,           // the host name does not resolve
  ConnectionRefused,      // nothing listens at host:port
  ConnectTimeout,         // no connection within the connect timeout
  ConnectionLost,         // the peer closed or reset the connection mid-stream
  AuthenticationRefused,  // the NTRIP caster answered 401 (user or password wrong)
  UnknownMountpoint,      // the caster answered with its SOURCETABLE or 404
  ProtocolError,          // an answer that is not NTRIP/HTTP as expected
  Stalled,                // connected, but no byte for the stall timeout
  ReadFailed,             // read()/poll() failed (errno text in the detail)
  WriteFailed,            // sending (request, GGA) failed
};

std::string_view byteSourceErrorKindName(ByteSourceErrorKind kind);
/// Errors that a retry cannot fix without a change by the user (spec, account,
/// mountpoint): reported, and retried only at the longest back-off.
bool isPermanentByteSourceError(ByteSourceErrorKind kind);

struct ByteSourceError {
  ByteSourceErrorKind kind = ByteSourceErrorKind::ReadFailed;
  std::string detail;  // for people; never parsed

  /// "authentication refused: caster 127.0.0.1:2101 answered 401 Unauthorized"
  std::string describe() const;
};

enum class ByteSourceStatus {
  Data,     // `size` bytes were written to the buffer (size > 0)
  Timeout,  // nothing within the timeout; the source is still usable
  Closed,   // the stream ended (end of a replayed file; a network peer that closes is
            // an Error ConnectionLost, a hang-up of a serial device too)
  Error,    // see `error`; the source is closed
};

struct ByteSourceRead {
  ByteSourceStatus status = ByteSourceStatus::Timeout;
  std::size_t size = 0;
  std::optional<ByteSourceError> error;  // set when status == Error

  static ByteSourceRead data(std::size_t size) { return {ByteSourceStatus::Data, size, std::nullopt}; }
  static ByteSourceRead timeout() { return {ByteSourceStatus::Timeout, 0, std::nullopt}; }
  static ByteSourceRead closed() { return {ByteSourceStatus::Closed, 0, std::nullopt}; }
  static ByteSourceRead failure(ByteSourceErrorKind kind, std::string detail) {
    return {ByteSourceStatus::Error, 0, ByteSourceError{kind, std::move(detail)}};
  }
};

struct ByteSourceCounters {
  std::uint64_t bytes = 0;       // delivered by read()
  std::uint64_t connects = 0;    // successful opens (connections, device opens)
  std::uint64_t reconnects = 0;  // opens after the first one (ReconnectingByteSource)
  std::uint64_t stalls = 0;      // Stalled errors
  std::uint64_t gga_sent = 0;    // NMEA GGA sentences sent upstream (NTRIP)
  std::map<ByteSourceErrorKind, std::uint64_t> errors_by_kind;
  std::optional<ByteSourceError> last_error;

  void addError(const ByteSourceError& error);
  std::uint64_t errors(ByteSourceErrorKind kind) const;
  std::uint64_t totalErrors() const;
};

class ByteSource {
 public:
  virtual ~ByteSource() = default;

  /// Up to `capacity` bytes into `buffer`, waiting at most `timeout`.
  virtual ByteSourceRead read(std::uint8_t* buffer, std::size_t capacity,
                              std::chrono::milliseconds timeout) = 0;
  /// "ntrip://user@caster.example:2101/MOUNT (v2)": never a password.
  virtual std::string describe() const = 0;
  /// Releases the device or connection; a later read() opens it again.
  virtual void close() = 0;

  const ByteSourceCounters& counters() const { return counters_; }

 protected:
  /// Records an error in the counters and returns it as a read result.
  ByteSourceRead fail(ByteSourceErrorKind kind, std::string detail);

  ByteSourceCounters counters_;
};

}  // namespace ppp
