#include "ppp_bayes_tree/io/transport/byte_source_spec.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include "ppp_bayes_tree/io/transport/credential_mask.h"
#include "ppp_bayes_tree/io/transport/file_replay_source.h"
#include "ppp_bayes_tree/io/transport/ntrip_client_source.h"
#include "ppp_bayes_tree/io/transport/reconnecting_byte_source.h"
#include "ppp_bayes_tree/io/transport/serial_port_source.h"
#include "ppp_bayes_tree/io/transport/tcp_client_source.h"

namespace ppp {
namespace {

[[noreturn]] void bad(const std::string& shown, const std::string& why) {
  throw ByteSourceSpecError("input spec '" + shown + "': " + why);
}

std::string percentDecode(const std::string& text, const std::string& shown) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      out += text[i];
      continue;
    }
    if (i + 2 >= text.size() || !std::isxdigit(static_cast<unsigned char>(text[i + 1])) ||
        !std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
      bad(shown, "a '%' not followed by two hex digits");
    }
    out += static_cast<char>(std::strtol(text.substr(i + 1, 2).c_str(), nullptr, 16));
    i += 2;
  }
  return out;
}

double number(const std::string& key, const std::string& value, const std::string& shown) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(x)) {
    bad(shown, "option " + key + "='" + value + "' is not a number");
  }
  return x;
}

int integer(const std::string& key, const std::string& value, const std::string& shown) {
  const double x = number(key, value, shown);
  if (x != std::floor(x) || std::fabs(x) > 1e9) bad(shown, "option " + key + "='" + value + "' is not an integer");
  return static_cast<int>(x);
}

int parsePort(const std::string& text, const std::string& shown) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 5) {
    bad(shown, "port '" + text + "' is not a number 1..65535");
  }
  const int port = std::atoi(text.c_str());
  if (port < 1 || port > 65535) bad(shown, "port " + text + " is outside 1..65535");
  return port;
}

// "host:port" (port optional when default_port is given); [v6] addresses in brackets.
void parseHostPort(const std::string& text, std::optional<int> default_port, ByteSourceSpec& spec,
                   const std::string& shown) {
  std::string host = text, port;
  if (!text.empty() && text[0] == '[') {
    const auto close = text.find(']');
    if (close == std::string::npos) bad(shown, "'[' without ']' in the host");
    host = text.substr(1, close - 1);
    if (close + 1 < text.size()) {
      if (text[close + 1] != ':') bad(shown, "expected ':port' after the ']'");
      port = text.substr(close + 2);
    }
  } else if (const auto colon = text.rfind(':'); colon != std::string::npos) {
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
  }
  if (host.empty()) bad(shown, "no host name");
  spec.host = host;
  if (port.empty()) {
    if (!default_port) bad(shown, "no port (write host:port)");
    spec.port = *default_port;
  } else {
    spec.port = parsePort(port, shown);
  }
}

// The spec text cut at "://" and "?": scheme, location (device, host, path) and query.
struct SpecParts {
  std::string scheme;
  std::string rest;
  std::string query;
};

// Step 1: the scheme, the location and the query of the spec text.
SpecParts splitSpecText(const std::string& text, const std::string& shown) {
  const auto scheme_end = text.find("://");
  if (scheme_end == std::string::npos) {
    bad(shown, "no scheme; expected serial://, tcp://, ntrip:// or file://");
  }
  SpecParts parts;
  parts.scheme = text.substr(0, scheme_end);
  parts.rest = text.substr(scheme_end + 3);
  if (const auto q = parts.rest.find('?'); q != std::string::npos) {
    parts.query = parts.rest.substr(q + 1);
    parts.rest = parts.rest.substr(0, q);
  }
  return parts;
}

// serial:///dev/ttyACM0: the device.
void parseSerialLocation(const SpecParts& parts, ByteSourceSpec& spec, std::set<std::string>& allowed,
                         const std::string& shown) {
  spec.kind = ByteSourceKind::Serial;
  if (parts.rest.empty()) bad(shown, "no device (serial:///dev/ttyACM0)");
  spec.device = parts.rest;
  allowed.insert("baud");
}

// tcp://host:port: host and port, no path.
void parseTcpLocation(const SpecParts& parts, ByteSourceSpec& spec, std::set<std::string>& allowed,
                      const std::string& shown) {
  spec.kind = ByteSourceKind::Tcp;
  std::string rest = parts.rest;
  if (rest.find('/') != std::string::npos && rest.find('/') + 1 != rest.size()) {
    bad(shown, "a tcp spec has no path (tcp://host:port)");
  }
  if (!rest.empty() && rest.back() == '/') rest.pop_back();
  parseHostPort(rest, std::nullopt, spec, shown);
  allowed.insert({"connect_timeout_s", "stall_timeout_s"});
}

// ntrip://user:password@host:port/MOUNT: percent-decoded user and password, host, port (2101), mountpoint.
void parseNtripLocation(const SpecParts& parts, ByteSourceSpec& spec, std::set<std::string>& allowed,
                        const std::string& shown) {
  spec.kind = ByteSourceKind::Ntrip;
  const std::string& rest = parts.rest;
  const auto at = rest.rfind('@');
  std::string hostpart = rest;
  if (at != std::string::npos) {
    const std::string userinfo = rest.substr(0, at);
    hostpart = rest.substr(at + 1);
    const auto colon = userinfo.find(':');
    spec.user = percentDecode(userinfo.substr(0, colon), shown);
    if (colon != std::string::npos) spec.password = percentDecode(userinfo.substr(colon + 1), shown);
  }
  const auto slash = hostpart.find('/');
  if (slash == std::string::npos || slash + 1 == hostpart.size()) {
    bad(shown, std::string("no mountpoint (ntrip://host:port/MOUNT)") +
                   (parts.query.find('@') != std::string::npos
                        ? "; a '?' in the user or the password must be written %3F (or use credentials=)"
                        : ""));
  }
  spec.mountpoint = hostpart.substr(slash + 1);
  if (spec.mountpoint.find_first_of("/ ") != std::string::npos) {
    bad(shown, "mountpoint '" + spec.mountpoint + "' holds '/' or a space");
  }
  parseHostPort(hostpart.substr(0, slash), 2101, spec, shown);
  allowed.insert({"connect_timeout_s", "stall_timeout_s", "version", "gga_period_s", "lat", "lon", "h", "credentials"});
}

// file:///path: the recording's path.
void parseFileLocation(const SpecParts& parts, ByteSourceSpec& spec, std::set<std::string>& allowed,
                       const std::string& shown) {
  spec.kind = ByteSourceKind::File;
  if (parts.rest.empty()) bad(shown, "no path (file:///path/x.rtcm3)");
  spec.path = parts.rest;
  allowed.insert({"speed", "byte_rate"});
}

// Step 2: the kind and location of the scheme; returns the option keys the scheme accepts.
std::set<std::string> parseLocation(const SpecParts& parts, ByteSourceSpec& spec, const std::string& shown) {
  std::set<std::string> allowed = {"format", "reconnect_min_s", "reconnect_max_s"};
  if (parts.scheme == "serial") {
    parseSerialLocation(parts, spec, allowed, shown);
  } else if (parts.scheme == "tcp") {
    parseTcpLocation(parts, spec, allowed, shown);
  } else if (parts.scheme == "ntrip") {
    parseNtripLocation(parts, spec, allowed, shown);
  } else if (parts.scheme == "file") {
    parseFileLocation(parts, spec, allowed, shown);
  } else {
    bad(shown, "unknown scheme '" + parts.scheme + "'; expected serial, tcp, ntrip or file");
  }
  return allowed;
}

// Step 3: the query's key=value options, each key known to the scheme and given once.
std::map<std::string, std::string> parseQueryOptions(const SpecParts& parts, const std::set<std::string>& allowed,
                                                     const std::string& shown) {
  const std::string& query = parts.query;
  std::map<std::string, std::string> options;
  std::size_t pos = 0;
  while (!query.empty() && pos <= query.size()) {
    const auto amp = query.find('&', pos);
    const std::string item = query.substr(pos, amp == std::string::npos ? std::string::npos : amp - pos);
    pos = amp == std::string::npos ? query.size() + 1 : amp + 1;
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) bad(shown, "option '" + item + "' is not key=value");
    const std::string key = item.substr(0, eq);
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& k : allowed) list += (list.empty() ? "" : ", ") + k;
      bad(shown, "unknown option '" + key + "' for " + parts.scheme + ":// (known: " + list + ")");
    }
    if (options.count(key)) bad(shown, "option '" + key + "' given twice");
    options[key] = item.substr(eq + 1);
  }
  return options;
}

// The NTRIP options: version, credentials and the GGA ones (gga_period_s in s, lat/lon in deg, h in m).
void applyNtripOption(const std::string& key, const std::string& value, ByteSourceSpec& spec,
                      const std::string& shown) {
  if (key == "version") {
    spec.ntrip_version = integer(key, value, shown);
    if (spec.ntrip_version != 1 && spec.ntrip_version != 2) bad(shown, "version=" + value + ": expected 1 or 2");
  } else if (key == "gga_period_s") {
    spec.gga_period_s = number(key, value, shown);
    if (*spec.gga_period_s <= 0.0) bad(shown, "gga_period_s must be > 0 s");
  } else if (key == "credentials") {
    if (value.empty()) bad(shown, "credentials= needs the path of a credentials file");
    spec.credentials_file = value;
  } else if (key == "lat") {
    spec.gga_latitude_deg = number(key, value, shown);
    if (std::fabs(*spec.gga_latitude_deg) > 90.0) bad(shown, "lat=" + value + " is outside -90..90 deg");
  } else if (key == "lon") {
    spec.gga_longitude_deg = number(key, value, shown);
    if (std::fabs(*spec.gga_longitude_deg) > 180.0) bad(shown, "lon=" + value + " is outside -180..180 deg");
  } else if (key == "h") {
    spec.gga_height_m = number(key, value, shown);
  }
}

// The timeouts and reconnection delays [s], each > 0 s.
void applyTimeoutOption_s(const std::string& key, const std::string& value, ByteSourceSpec& spec,
                          const std::string& shown) {
  const double x = number(key, value, shown);
  if (x <= 0.0) bad(shown, key + " must be > 0 s");
  if (key == "connect_timeout_s") spec.connect_timeout_s = x;
  if (key == "stall_timeout_s") spec.stall_timeout_s = x;
  if (key == "reconnect_min_s") spec.reconnect_min_s = x;
  if (key == "reconnect_max_s") spec.reconnect_max_s = x;
}

// Step 4: one option's value checked and stored in the spec.
void applyOption(const std::string& key, const std::string& value, ByteSourceSpec& spec, const std::string& shown) {
  if (key == "format") {
    if (value != "rtcm3" && value != "ubx") bad(shown, "format='" + value + "': expected rtcm3 or ubx");
    spec.format = value;
  } else if (key == "baud") {
    spec.baud = integer(key, value, shown);
    if (!isSupportedBaudRate(spec.baud)) {
      bad(shown, "baud=" + value + " is not one of 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600");
    }
  } else if (key == "speed") {
    spec.speed = number(key, value, shown);
    if (spec.speed < 0.0) bad(shown, "speed must be >= 0 (0: as fast as read)");
  } else if (key == "byte_rate") {
    spec.byte_rate_bytes_per_s = number(key, value, shown);
    if (spec.byte_rate_bytes_per_s <= 0.0) bad(shown, "byte_rate must be > 0 bytes/s");
  } else if (key == "connect_timeout_s" || key == "stall_timeout_s" || key == "reconnect_min_s" ||
             key == "reconnect_max_s") {
    applyTimeoutOption_s(key, value, spec, shown);
  } else {
    applyNtripOption(key, value, spec, shown);
  }
}

// Step 5: the options that only make sense together (reconnection delays, GGA period and position).
void checkOptionCombinations(const ByteSourceSpec& spec, const std::string& shown) {
  if (spec.reconnect_min_s > spec.reconnect_max_s) bad(shown, "reconnect_min_s is above reconnect_max_s");
  if (spec.gga_period_s && (!spec.gga_latitude_deg || !spec.gga_longitude_deg)) {
    bad(shown, "gga_period_s needs lat and lon (and h) for the GGA position");
  }
  if (!spec.gga_period_s && (spec.gga_latitude_deg || spec.gga_longitude_deg || spec.gga_height_m)) {
    bad(shown, "lat/lon/h are given but gga_period_s is not: no GGA would be sent");
  }
}

}  // namespace

ByteSourceSpec parseByteSourceSpec(const std::string& text) {
  // Shown in errors and logs: the password hidden however the spec is mistyped.
  const std::string shown = maskCredentials(text);
  ByteSourceSpec spec;
  const SpecParts parts = splitSpecText(text, shown);                             // 1. scheme, location, query
  const std::set<std::string> allowed = parseLocation(parts, spec, shown);       // 2. kind and location
  const auto options = parseQueryOptions(parts, allowed, shown);                 // 3. key=value options
  for (const auto& [key, value] : options) applyOption(key, value, spec, shown); // 4. each option checked
  checkOptionCombinations(spec, shown);                                          // 5. options together
  spec.text_without_password = shown;
  return spec;
}

std::unique_ptr<ByteSource> openSingleByteSource(const ByteSourceSpec& spec) {
  const auto ms = [](double s) { return std::chrono::milliseconds(static_cast<long long>(std::llround(s * 1000.0))); };
  switch (spec.kind) {
    case ByteSourceKind::Serial: return std::make_unique<SerialPortSource>(spec.device, spec.baud);
    case ByteSourceKind::Tcp:
      return std::make_unique<TcpClientSource>(spec.host, spec.port, ms(spec.connect_timeout_s), ms(spec.stall_timeout_s));
    case ByteSourceKind::Ntrip: {
      NtripClientOptions options;
      options.host = spec.host;
      options.port = spec.port;
      options.mountpoint = spec.mountpoint;
      options.user = spec.user;
      options.password = spec.password;
      options.version = spec.ntrip_version;
      options.connect_timeout = ms(spec.connect_timeout_s);
      options.stall_timeout = ms(spec.stall_timeout_s);
      if (spec.gga_period_s) {
        options.gga_period = ms(*spec.gga_period_s);
        options.gga_latitude_deg = *spec.gga_latitude_deg;
        options.gga_longitude_deg = *spec.gga_longitude_deg;
        options.gga_height_m = spec.gga_height_m.value_or(0.0);
      }
      return std::make_unique<NtripClientSource>(options);
    }
    case ByteSourceKind::File: {
      std::error_code ec;
      if (std::filesystem::is_directory(spec.path, ec))
        bad(spec.text_without_password, spec.path + " is a directory, not a recording (file:///path/x.rtcm3)");
      StreamFormat format = StreamFormat::Unknown;
      if (spec.format) format = *spec.format == "ubx" ? StreamFormat::Ubx : StreamFormat::Rtcm3;
      return std::make_unique<FileReplaySource>(spec.path, spec.speed, spec.byte_rate_bytes_per_s, format);
    }
  }
  return nullptr;
}

std::unique_ptr<ByteSource> openByteSource(const ByteSourceSpec& spec) {
  if (spec.kind == ByteSourceKind::File) return openSingleByteSource(spec);
  const auto ms = [](double s) { return std::chrono::milliseconds(static_cast<long long>(std::llround(s * 1000.0))); };
  return std::make_unique<ReconnectingByteSource>([spec] { return openSingleByteSource(spec); },
                                                  ms(spec.reconnect_min_s), ms(spec.reconnect_max_s));
}

}  // namespace ppp
