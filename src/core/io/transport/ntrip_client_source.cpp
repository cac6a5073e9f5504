#include "ppp_bayes_tree/io/transport/ntrip_client_source.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>

#include "ppp_bayes_tree/io/transport/nmea_gga.h"
#include "ppp_bayes_tree/io/untrusted_text.h"

namespace ppp {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kMaxHeaderBytes = 64 * 1024;

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string firstLine(const std::string& text) {
  const auto end = text.find_first_of("\r\n");
  return text.substr(0, end);
}

double utcSecondsOfDay() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const double s = std::chrono::duration<double>(now).count();
  return s - 86400.0 * std::floor(s / 86400.0);
}

}  // namespace

std::string basicAuthorization(const std::string& user, const std::string& password) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const std::string in = user + ":" + password;
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = static_cast<unsigned char>(in[i]) << 16;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return "Basic " + out;
}

NtripClientSource::NtripClientSource(NtripClientOptions options) : options_(std::move(options)) {}

std::string NtripClientSource::describe() const {
  std::string text = "ntrip://";
  if (!options_.user.empty()) text += options_.user + "@";
  text += options_.host + ":" + std::to_string(options_.port) + "/" + options_.mountpoint +
          " (NTRIP v" + std::to_string(options_.version) + ")";
  return text;
}

void NtripClientSource::close() {
  connection_.close();
  streaming_ = false;
  raw_.clear();
  chunk_left_.reset();
  stream_ended_ = false;
}

std::optional<ByteSourceError> NtripClientSource::openStream(Clock::time_point deadline) {
  const std::string where = options_.host + ":" + std::to_string(options_.port);
  chunked_ = false;
  status_line_.clear();
  if (auto error = connection_.connect(options_.host, options_.port, options_.connect_timeout)) {
    error->detail = "caster " + error->detail;
    return error;
  }
  ++counters_.connects;
  std::string request = "GET /" + options_.mountpoint + (options_.version == 2 ? " HTTP/1.1\r\n" : " HTTP/1.0\r\n");
  if (options_.version == 2) {
    request += "Host: " + options_.host + ":" + std::to_string(options_.port) + "\r\n";
    request += "Ntrip-Version: Ntrip/2.0\r\n";
  }
  request += "User-Agent: NTRIP ppp_bayes_tree/0.1\r\n";
  if (!options_.user.empty() || !options_.password.empty()) {
    request += "Authorization: " + basicAuthorization(options_.user, options_.password) + "\r\n";
  }
  if (options_.version == 2) request += "Connection: close\r\n";
  request += "\r\n";
  if (auto error = connection_.sendAll(request)) return error;

  // Read the answer header: up to the blank line, or the first line for v1 "ICY 200 OK".
  std::string header;
  std::uint8_t chunk[4096];
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) {
      return ByteSourceError{ByteSourceErrorKind::Stalled,
                             "caster " + where + " sent no complete answer to the request for /" + options_.mountpoint};
    }
    ByteSourceRead got = connection_.receive(chunk, sizeof(chunk), left);
    if (got.status == ByteSourceStatus::Error) return got.error;
    const bool closed = got.status == ByteSourceStatus::Closed;
    header.append(reinterpret_cast<const char*>(chunk), got.size);
    const std::string line = firstLine(header);
    const std::string shown_line = printableText(line);  // the caster's text, escaped for logs
    const bool line_done = header.find('\n') != std::string::npos;
    if (line_done && line.rfind("ICY 200", 0) == 0) {
      // v1 answer: the stream follows the status line (and, for some casters, a blank line).
      std::size_t body = header.find('\n') + 1;
      if (header.compare(body, 2, "\r\n") == 0) body += 2;
      status_line_ = shown_line;
      raw_.assign(header.begin() + static_cast<long>(body), header.end());
      return std::nullopt;
    }
    const std::size_t end = header.find("\r\n\r\n");
    if (line_done && (end != std::string::npos || closed)) {
      status_line_ = shown_line;
      const std::string fields = lower(header.substr(0, end == std::string::npos ? header.size() : end));
      if (line.rfind("SOURCETABLE", 0) == 0 ||
          (fields.find("content-type: gnss/sourcetable") != std::string::npos)) {
        return ByteSourceError{ByteSourceErrorKind::UnknownMountpoint,
                               "caster " + where + " has no mountpoint '" + options_.mountpoint +
                                   "' (it answered with its source table)"};
      }
      const auto space = line.find(' ');
      const int code = space == std::string::npos ? 0 : std::atoi(line.c_str() + space + 1);
      if (code == 401 || code == 403) {
        return ByteSourceError{ByteSourceErrorKind::AuthenticationRefused,
                               "caster " + where + " refused user '" + options_.user + "' for /" +
                                   options_.mountpoint + " (" + shown_line + ")"};
      }
      if (code == 404) {
        return ByteSourceError{ByteSourceErrorKind::UnknownMountpoint,
                               "caster " + where + " has no mountpoint '" + options_.mountpoint + "' (" + shown_line + ")"};
      }
      if (line.rfind("HTTP/", 0) != 0 || code != 200) {
        return ByteSourceError{ByteSourceErrorKind::ProtocolError,
                               "caster " + where + " answered '" + shown_line + "' to the request for /" + options_.mountpoint};
      }
      chunked_ = fields.find("transfer-encoding: chunked") != std::string::npos;
      if (end == std::string::npos) return std::nullopt;
      raw_.assign(header.begin() + static_cast<long>(end + 4), header.end());
      return std::nullopt;
    }
    if (closed) {
      return ByteSourceError{ByteSourceErrorKind::ConnectionLost,
                             "caster " + where + " closed the connection before answering ('" + shown_line + "')"};
    }
    if (header.size() > kMaxHeaderBytes) {
      return ByteSourceError{ByteSourceErrorKind::ProtocolError,
                             "caster " + where + " sent " + std::to_string(header.size()) + " bytes without a header end"};
    }
  }
}

std::optional<ByteSourceError> NtripClientSource::sendGgaIfDue() {
  if (!options_.gga_period || Clock::now() < next_gga_time_) return std::nullopt;
  const std::string gga = makeNmeaGga(options_.gga_latitude_deg, options_.gga_longitude_deg,
                                      options_.gga_height_m, utcSecondsOfDay());
  if (auto error = connection_.sendAll(gga)) return error;
  ++counters_.gga_sent;
  next_gga_time_ = Clock::now() + *options_.gga_period;
  return std::nullopt;
}

std::size_t NtripClientSource::takePayload(std::uint8_t* buffer, std::size_t capacity,
                                           std::optional<ByteSourceError>& error) {
  if (!chunked_) {
    const std::size_t n = std::min(capacity, raw_.size());
    std::copy(raw_.begin(), raw_.begin() + static_cast<long>(n), buffer);
    raw_.erase(raw_.begin(), raw_.begin() + static_cast<long>(n));
    return n;
  }
  // Chunked: "<hex size>[;ext]\r\n<data>\r\n" ... "0\r\n\r\n" (RFC 7230 4.1).
  std::size_t out = 0;
  std::size_t pos = 0;
  while (out < capacity && pos < raw_.size() && !stream_ended_) {
    if (chunk_left_ && *chunk_left_ > 0) {
      const std::size_t n = std::min({capacity - out, raw_.size() - pos, *chunk_left_});
      std::copy(raw_.begin() + static_cast<long>(pos), raw_.begin() + static_cast<long>(pos + n), buffer + out);
      out += n;
      pos += n;
      *chunk_left_ -= n;
      continue;
    }
    std::size_t line_start = pos;
    if (chunk_left_) {  // a chunk just ended: its CRLF
      if (raw_.size() - pos < 2) break;
      if (raw_[pos] != '\r' || raw_[pos + 1] != '\n') {
        error = ByteSourceError{ByteSourceErrorKind::ProtocolError, "chunked transfer: no CRLF after a chunk"};
        break;
      }
      line_start = pos + 2;
    }
    const auto lf = std::find(raw_.begin() + static_cast<long>(line_start), raw_.end(), '\n');
    if (lf == raw_.end()) {
      if (raw_.size() - line_start > 1024) {
        error = ByteSourceError{ByteSourceErrorKind::ProtocolError, "chunked transfer: chunk size line too long"};
      }
      break;
    }
    const std::string line(raw_.begin() + static_cast<long>(line_start), lf);
    std::size_t size = 0;
    std::size_t digits = 0;
    for (char c : line) {
      if (!std::isxdigit(static_cast<unsigned char>(c))) break;
      size = size * 16 + static_cast<std::size_t>(std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : (std::tolower(c) - 'a' + 10));
      ++digits;
    }
    if (digits == 0 || digits > 8) {
      error = ByteSourceError{ByteSourceErrorKind::ProtocolError,
                              "chunked transfer: bad chunk size line '" + printableText(line) + "'"};
      break;
    }
    pos = static_cast<std::size_t>(lf - raw_.begin()) + 1;
    chunk_left_ = size;
    if (size == 0) stream_ended_ = true;
  }
  raw_.erase(raw_.begin(), raw_.begin() + static_cast<long>(pos));
  return out;
}

ByteSourceRead NtripClientSource::read(std::uint8_t* buffer, std::size_t capacity,
                                       std::chrono::milliseconds timeout) {
  if (!streaming_) {
    const auto deadline = Clock::now() + options_.connect_timeout + options_.stall_timeout;
    if (auto error = openStream(deadline)) {
      close();
      return fail(error->kind, std::move(error->detail));
    }
    streaming_ = true;
    last_byte_time_ = Clock::now();
    next_gga_time_ = Clock::now();
  }
  const auto started = Clock::now();
  while (true) {
    if (auto error = sendGgaIfDue()) {
      close();
      return fail(error->kind, std::move(error->detail));
    }
    std::optional<ByteSourceError> error;
    const std::size_t n = takePayload(buffer, capacity, error);
    if (error) {
      close();
      return fail(error->kind, std::move(error->detail));
    }
    if (n > 0) {
      counters_.bytes += n;
      return ByteSourceRead::data(n);
    }
    if (stream_ended_) {
      close();
      return fail(ByteSourceErrorKind::ConnectionLost, describe() + ": the caster ended the stream");
    }
    const auto now = Clock::now();
    if (now - last_byte_time_ >= options_.stall_timeout) {
      close();
      return fail(ByteSourceErrorKind::Stalled,
                  describe() + ": no byte for " + std::to_string(options_.stall_timeout.count()) + " ms");
    }
    auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(
        std::min(started + timeout, last_byte_time_ + options_.stall_timeout) - now);
    if (options_.gga_period) {
      wait = std::min(wait, std::chrono::duration_cast<std::chrono::milliseconds>(next_gga_time_ - now));
    }
    if (now >= started + timeout) return ByteSourceRead::timeout();
    std::uint8_t chunk[8192];
    ByteSourceRead got = connection_.receive(chunk, sizeof(chunk), std::max(wait, std::chrono::milliseconds(0)));
    if (got.status == ByteSourceStatus::Data) {
      raw_.insert(raw_.end(), chunk, chunk + got.size);
      last_byte_time_ = Clock::now();
      continue;
    }
    if (got.status == ByteSourceStatus::Closed) {
      close();
      return fail(ByteSourceErrorKind::ConnectionLost, describe() + ": the caster closed the connection");
    }
    if (got.status == ByteSourceStatus::Error) {
      close();
      return fail(got.error->kind, describe() + ": " + got.error->detail);
    }
    if (Clock::now() >= started + timeout && Clock::now() - last_byte_time_ < options_.stall_timeout) {
      return ByteSourceRead::timeout();
    }
  }
}

}  // namespace ppp
