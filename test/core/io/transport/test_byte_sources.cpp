// Live inputs (io/transport/byte_source.h and its sources): the input spec parser, the
// NMEA GGA sentence and Basic authorization against published examples, and the
// sources against real peers on loopback: RTKLIB's str2str as an NTRIP caster
// and as a TCP server streaming the recordings of ../shared/data/streams, a
// scripted NTRIP v2 caster (chunked transfer, 404, stall, GGA upstream), and a
// kernel pseudo-terminal pair as the serial port.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "loopback_servers.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/transport/byte_source_spec.h"
#include "ppp_bayes_tree/io/transport/file_replay_source.h"
#include "ppp_bayes_tree/io/transport/nmea_gga.h"
#include "ppp_bayes_tree/io/transport/ntrip_client_source.h"
#include "ppp_bayes_tree/io/transport/reconnecting_byte_source.h"
#include "ppp_bayes_tree/io/transport/serial_port_source.h"
#include "ppp_bayes_tree/io/transport/tcp_client_source.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "test_support.h"

namespace ppp {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using test::dataPath;
using test::readFileBytes;

bool streamsAvailable() { return std::filesystem::is_directory(dataPath("streams/rtcm")); }
#define REQUIRE_STREAMS()                                                                     \
  if (!streamsAvailable()) GTEST_SKIP() << "no ../shared/data/streams (set PPP_SHARED_DATA)"
#define REQUIRE_STR2STR()                                                                     \
  if (!test::str2strAvailable()) GTEST_SKIP() << "RTKLIB str2str is not installed (Debian package rtklib)"

/// Reads from `source` until `expected` bytes arrived, an error, or `limit`.
std::string readBytes(ByteSource& source, std::size_t expected, std::chrono::milliseconds limit,
                      std::optional<ByteSourceError>* error = nullptr) {
  std::string out;
  std::uint8_t buffer[4096];
  const auto until = Clock::now() + limit;
  while (out.size() < expected && Clock::now() < until) {
    const ByteSourceRead got = source.read(buffer, sizeof(buffer), 100ms);
    if (got.status == ByteSourceStatus::Data) out.append(reinterpret_cast<const char*>(buffer), got.size);
    if (got.status == ByteSourceStatus::Closed) break;
    if (got.status == ByteSourceStatus::Error) {
      if (error) *error = got.error;
      if (error) break;
    }
  }
  return out;
}

/// Reads until the source reports Timeout while connected (the peer accepted
/// us; a failed open gives Error, and a ReconnectingByteSource then has no source).
bool waitConnected(ByteSource& source, std::chrono::milliseconds limit) {
  std::uint8_t buffer[256];
  const auto until = Clock::now() + limit;
  while (Clock::now() < until) {
    const ByteSourceRead got = source.read(buffer, sizeof(buffer), 50ms);
    if (got.status != ByteSourceStatus::Timeout || source.counters().connects == 0) continue;
    const auto* reconnecting = dynamic_cast<const ReconnectingByteSource*>(&source);
    if (reconnecting == nullptr || reconnecting->hasSource()) return true;
  }
  return false;
}

std::vector<std::vector<std::uint8_t>> rtcmFrames(const std::string& bytes, StreamCounters* counters = nullptr) {
  Rtcm3Framer framer;
  std::vector<std::vector<std::uint8_t>> frames;
  framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
              [&](const Rtcm3Frame& f) { frames.push_back(f.payload); });
  framer.finish();
  if (counters) *counters = framer.counters();
  return frames;
}

// ---------------------------------------------------------------------------
// Spec parser
// ---------------------------------------------------------------------------

TEST(ByteSourceSpec, ParsesTheFourKinds) {
  const ByteSourceSpec serial = parseByteSourceSpec("serial:///dev/ttyACM0?baud=460800");
  EXPECT_EQ(serial.kind, ByteSourceKind::Serial);
  EXPECT_EQ(serial.device, "/dev/ttyACM0");
  EXPECT_EQ(serial.baud, 460800);
  EXPECT_EQ(parseByteSourceSpec("serial:///dev/ttyUSB1").baud, 115200);

  const ByteSourceSpec tcp = parseByteSourceSpec("tcp://192.168.1.20:5018?stall_timeout_s=3");
  EXPECT_EQ(tcp.kind, ByteSourceKind::Tcp);
  EXPECT_EQ(tcp.host, "192.168.1.20");
  EXPECT_EQ(tcp.port, 5018);
  EXPECT_DOUBLE_EQ(tcp.stall_timeout_s, 3.0);

  const ByteSourceSpec ntrip = parseByteSourceSpec(
      "ntrip://alice:s%40cret:x@caster.example.org:2102/SSRA00IGS0?version=1&gga_period_s=10&lat=55.5&lon=-8.25&h=50");
  EXPECT_EQ(ntrip.kind, ByteSourceKind::Ntrip);
  EXPECT_EQ(ntrip.user, "alice");
  EXPECT_EQ(ntrip.password, "s@cret:x");
  EXPECT_EQ(ntrip.host, "caster.example.org");
  EXPECT_EQ(ntrip.port, 2102);
  EXPECT_EQ(ntrip.mountpoint, "SSRA00IGS0");
  EXPECT_EQ(ntrip.ntrip_version, 1);
  ASSERT_TRUE(ntrip.gga_period_s && ntrip.gga_latitude_deg && ntrip.gga_longitude_deg && ntrip.gga_height_m);
  EXPECT_DOUBLE_EQ(*ntrip.gga_period_s, 10.0);
  EXPECT_DOUBLE_EQ(*ntrip.gga_longitude_deg, -8.25);
  EXPECT_EQ(ntrip.text_without_password.find("s%40cret"), std::string::npos) << ntrip.text_without_password;
  EXPECT_NE(ntrip.text_without_password.find("alice:***@caster.example.org"), std::string::npos)
      << ntrip.text_without_password;

  const ByteSourceSpec anonymous = parseByteSourceSpec("ntrip://caster.example.org/MOUNT");
  EXPECT_EQ(anonymous.port, 2101);
  EXPECT_EQ(anonymous.ntrip_version, 2);
  EXPECT_TRUE(anonymous.user.empty());

  const ByteSourceSpec file = parseByteSourceSpec("file:///data/x.rtcm3?speed=2.5&format=rtcm3");
  EXPECT_EQ(file.kind, ByteSourceKind::File);
  EXPECT_EQ(file.path, "/data/x.rtcm3");
  EXPECT_DOUBLE_EQ(file.speed, 2.5);
  EXPECT_EQ(file.format.value_or(""), "rtcm3");
}

TEST(ByteSourceSpec, RejectsBadSpecsWithAClearMessage) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/dev/ttyACM0", "no scheme"},
      {"udp://host:1", "unknown scheme 'udp'"},
      {"serial://", "no device"},
      {"serial:///dev/ttyACM0?baud=12345", "baud=12345 is not one of"},
      {"serial:///dev/ttyACM0?baud=fast", "not a number"},
      {"tcp://host", "no port"},
      {"tcp://host:70000", "outside 1..65535"},
      {"tcp://:5000", "no host"},
      {"ntrip://u:p@host:2101", "no mountpoint"},
      {"ntrip://u:p@host/M?version=3", "expected 1 or 2"},
      {"ntrip://u:p@host/M?gga_period_s=10", "needs lat and lon"},
      {"ntrip://u:p@host/M?lat=10&lon=10", "gga_period_s is not"},
      {"ntrip://u:p@host/M?gga_period_s=5&lat=95&lon=0", "outside -90..90"},
      {"ntrip://u:p@host/M?mount=X", "unknown option 'mount'"},
      {"file:///x.rtcm3?speed=-1", "speed must be >= 0"},
      {"file:///x.rtcm3?speed=1&speed=2", "given twice"},
      {"file:///x.rtcm3?format=sbf", "expected rtcm3 or ubx"},
      {"file:///x.rtcm3?baud=9600", "unknown option 'baud' for file://"},
      {"tcp://h:1?reconnect_min_s=10&reconnect_max_s=5", "reconnect_min_s is above"},
  };
  for (const auto& [spec, expected] : cases) {
    try {
      parseByteSourceSpec(spec);
      ADD_FAILURE() << spec << " was accepted";
    } catch (const ByteSourceSpecError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << spec << " -> " << e.what();
    }
  }
  // The password never appears in an error.
  try {
    parseByteSourceSpec("ntrip://bob:hunter2@host/M?bogus=1");
    ADD_FAILURE() << "accepted";
  } catch (const ByteSourceSpecError& e) {
    EXPECT_EQ(std::string(e.what()).find("hunter2"), std::string::npos) << e.what();
  }
}

TEST(ByteSourceSpec, DescribeNeverShowsThePassword) {
  const auto source = openByteSource(parseByteSourceSpec("ntrip://bob:hunter2@127.0.0.1:1/MNT"));
  EXPECT_EQ(source->describe().find("hunter2"), std::string::npos) << source->describe();
  EXPECT_NE(source->describe().find("bob@127.0.0.1:1/MNT"), std::string::npos) << source->describe();
}

// ---------------------------------------------------------------------------
// GGA and Basic authorization: published examples
// ---------------------------------------------------------------------------

TEST(NmeaGga, ChecksumOfThePublishedExample) {
  // The GGA example of the NMEA 0183 descriptions (e.g. gpsd's "NMEA Revealed",
  // GGA section): checksum 47.
  EXPECT_EQ(nmeaChecksum("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47"), 0x47);
}

TEST(NmeaGga, SentenceFieldsAndChecksum) {
  // 48 deg 07.038' N, 11 deg 31.000' E (the example's position), 12:35:19 UTC.
  const std::string gga = makeNmeaGga(48.0 + 7.038 / 60.0, 11.0 + 31.0 / 60.0, 545.4, 12 * 3600 + 35 * 60 + 19);
  EXPECT_EQ(gga.rfind("$GPGGA,123519.00,4807.03800,N,01131.00000,E,1,", 0), 0u) << gga;
  ASSERT_GE(gga.size(), 5u);
  EXPECT_EQ(gga.substr(gga.size() - 2), "\r\n");
  const std::string hex = gga.substr(gga.size() - 4, 2);
  EXPECT_EQ(std::stoi(hex, nullptr, 16), nmeaChecksum(gga)) << gga;
  const std::string south_west = makeNmeaGga(-33.5, -70.25, 10.0, 0.0);
  EXPECT_NE(south_west.find(",3330.00000,S,07015.00000,W,"), std::string::npos) << south_west;
}

TEST(NtripClient, BasicAuthorizationOfRfc7617Example) {
  // RFC 7617, section 2: user "Aladdin", password "open sesame".
  EXPECT_EQ(basicAuthorization("Aladdin", "open sesame"), "Basic QWxhZGRpbjpvcGVuIHNlc2FtZQ==");
}

// ---------------------------------------------------------------------------
// NTRIP and TCP against str2str
// ---------------------------------------------------------------------------

NtripClientOptions ntripOptions(int port, const std::string& mount, const std::string& password, int version) {
  NtripClientOptions o;
  o.host = "127.0.0.1";
  o.port = port;
  o.mountpoint = mount;
  o.user = "rover";
  o.password = password;
  o.version = version;
  o.connect_timeout = 2000ms;
  o.stall_timeout = 5000ms;
  return o;
}

/// A str2str caster on a free port, listening (probed with a refused-free connect).
int startCaster(std::unique_ptr<test::Str2str>& caster, int port = 0) {
  if (port == 0) port = test::freeLoopbackPort();
  caster = std::make_unique<test::Str2str>("ntripc://rover:secret@:" + std::to_string(port) + "/MSM7");
  for (int i = 0; i < 50; ++i) {
    TcpConnection probe;
    if (!probe.connect("127.0.0.1", port, 200ms)) return port;
    std::this_thread::sleep_for(50ms);
  }
  return port;
}

class Str2strNtrip : public ::testing::TestWithParam<int> {};

TEST_P(Str2strNtrip, BytesReceivedEqualTheRecording) {
  REQUIRE_STREAMS();
  REQUIRE_STR2STR();
  const std::string recording = readFileBytes(dataPath("streams/rtcm/msm7.rtcm"));
  std::unique_ptr<test::Str2str> caster;
  const int port = startCaster(caster);
  NtripClientSource client(ntripOptions(port, "MSM7", "secret", GetParam()));
  ASSERT_TRUE(waitConnected(client, 5s)) << client.counters().last_error.value_or(ByteSourceError{}).describe();
  EXPECT_EQ(client.statusLine(), "ICY 200 OK");  // str2str answers v2 requests in v1 style too
  std::thread feeder([&] {
    caster->write(recording);
    caster->closeInput();
  });
  const std::string received = readBytes(client, recording.size(), 10s);
  feeder.join();
  EXPECT_EQ(received.size(), recording.size());
  EXPECT_TRUE(received == recording) << "the bytes differ from msm7.rtcm";
  EXPECT_EQ(client.counters().bytes, recording.size());
  EXPECT_EQ(client.counters().totalErrors(), 0u);
}

INSTANTIATE_TEST_SUITE_P(NtripVersions, Str2strNtrip, ::testing::Values(1, 2));

TEST(Str2strNtripErrors, WrongPasswordIsAuthenticationRefused) {
  REQUIRE_STR2STR();
  std::unique_ptr<test::Str2str> caster;
  const int port = startCaster(caster);
  for (int version : {1, 2}) {
    NtripClientSource client(ntripOptions(port, "MSM7", "wrong", version));
    std::uint8_t buffer[64];
    const ByteSourceRead got = client.read(buffer, sizeof(buffer), 2000ms);
    ASSERT_EQ(got.status, ByteSourceStatus::Error);
    EXPECT_EQ(got.error->kind, ByteSourceErrorKind::AuthenticationRefused) << got.error->describe();
    EXPECT_NE(got.error->detail.find("401"), std::string::npos) << got.error->describe();
    EXPECT_EQ(got.error->describe().find("wrong"), std::string::npos) << got.error->describe();
    EXPECT_EQ(client.counters().errors(ByteSourceErrorKind::AuthenticationRefused), 1u);
  }
}

TEST(Str2strNtripErrors, UnknownMountpointFromTheSourceTable) {
  REQUIRE_STR2STR();
  std::unique_ptr<test::Str2str> caster;
  const int port = startCaster(caster);
  NtripClientSource client(ntripOptions(port, "NOSUCH", "secret", 1));
  std::uint8_t buffer[64];
  const ByteSourceRead got = client.read(buffer, sizeof(buffer), 2000ms);
  ASSERT_EQ(got.status, ByteSourceStatus::Error);
  EXPECT_EQ(got.error->kind, ByteSourceErrorKind::UnknownMountpoint) << got.error->describe();
  EXPECT_NE(got.error->detail.find("NOSUCH"), std::string::npos);
}

TEST(Str2strNtripErrors, PermanentErrorIsRetriedOnlyAtTheLongestBackoff) {
  REQUIRE_STR2STR();
  std::unique_ptr<test::Str2str> caster;
  const int port = startCaster(caster);
  ReconnectingByteSource source(
      [port] { return std::make_unique<NtripClientSource>(ntripOptions(port, "MSM7", "wrong", 2)); }, 50ms, 3000ms);
  std::optional<ByteSourceError> error;
  readBytes(source, 1, 1500ms, &error);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->kind, ByteSourceErrorKind::AuthenticationRefused);
  // Keep reading for 1.5 s: no second attempt (the back-off is the max, 3 s).
  readBytes(source, 1, 1500ms);
  EXPECT_EQ(source.counters().errors(ByteSourceErrorKind::AuthenticationRefused), 1u);
  EXPECT_EQ(source.counters().reconnects, 0u);
  EXPECT_EQ(source.currentBackoff(), 3000ms);
}

TEST(Str2strNtripErrors, CasterKilledMidStreamReconnectsAndResumes) {
  REQUIRE_STREAMS();
  REQUIRE_STR2STR();
  const std::string recording = readFileBytes(dataPath("streams/rtcm/msm7.rtcm"));
  const std::size_t half = recording.size() / 2;
  std::unique_ptr<test::Str2str> caster;
  const int port = startCaster(caster);
  ReconnectingByteSource source(
      [port] { return std::make_unique<NtripClientSource>(ntripOptions(port, "MSM7", "secret", 2)); }, 100ms, 800ms);
  ASSERT_TRUE(waitConnected(source, 5s));
  std::thread first_half([&] { caster->write(recording.substr(0, half)); });
  std::string received = readBytes(source, half, 10s);
  first_half.join();
  ASSERT_EQ(received.size(), half);
  caster->stop();  // SIGKILL mid-stream

  // The loss is reported, then attempts fail (nothing listens) with a growing back-off.
  std::optional<ByteSourceError> error;
  readBytes(source, 1, 2s, &error);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->kind, ByteSourceErrorKind::ConnectionLost) << error->describe();
  readBytes(source, 1, 1500ms);
  EXPECT_GE(source.counters().errors(ByteSourceErrorKind::ConnectionRefused), 1u);
  EXPECT_GT(source.currentBackoff(), 100ms);

  // A new caster on the same port: reconnect, then the rest of the stream.
  startCaster(caster, port);
  const auto reconnects_before = source.counters().reconnects;
  const auto until = Clock::now() + 5s;
  bool connected = false;
  while (!connected && Clock::now() < until) {
    std::uint8_t buffer[256];
    const auto got = source.read(buffer, sizeof(buffer), 100ms);
    connected = got.status == ByteSourceStatus::Timeout && source.hasSource() &&
                source.counters().reconnects > reconnects_before && source.counters().last_error &&
                source.counters().connects >= 2;
    ASSERT_NE(got.status, ByteSourceStatus::Data);
  }
  // A Timeout from a made source means the caster answered 200 (errors drop the source).
  ASSERT_TRUE(connected);
  std::thread feeder([&] {
    caster->write(recording.substr(half));
    caster->closeInput();
  });
  received += readBytes(source, recording.size() - half, 10s);
  feeder.join();
  EXPECT_TRUE(received == recording) << received.size() << " of " << recording.size() << " bytes";
  EXPECT_GE(source.counters().reconnects, 2u);  // at least one refused attempt, then the good one
  EXPECT_GE(source.counters().connects, 2u);
  EXPECT_EQ(source.counters().bytes, recording.size());
}

TEST(Str2strTcp, TcpServerBytesEqualTheRecording) {
  REQUIRE_STREAMS();
  REQUIRE_STR2STR();
  const std::string recording = readFileBytes(dataPath("streams/rtcm/clk.rtcm"));
  const int port = test::freeLoopbackPort();
  test::Str2str server("tcpsvr://:" + std::to_string(port));
  auto spec = parseByteSourceSpec("tcp://127.0.0.1:" + std::to_string(port) + "?reconnect_min_s=0.05");
  auto source = openByteSource(spec);
  ASSERT_TRUE(waitConnected(*source, 5s));
  // str2str's tcpsvr accepts in its own cycle: give it that before the data.
  std::this_thread::sleep_for(500ms);
  std::thread feeder([&] {  // str2str drops what its client does not read in time: read meanwhile
    server.write(recording);
    server.closeInput();
  });
  const std::string received = readBytes(*source, recording.size(), 10s);
  feeder.join();
  EXPECT_EQ(received.size(), recording.size());
  EXPECT_TRUE(received == recording);
}

// ---------------------------------------------------------------------------
// NTRIP v2 chunked, 404, stall, GGA: a scripted caster
// ---------------------------------------------------------------------------

TEST(ScriptedCaster, NtripV2ChunkedTransferIsDecoded) {
  REQUIRE_STREAMS();
  const std::string recording = readFileBytes(dataPath("streams/rtcm/msm7.rtcm"));
  std::string request;
  test::ScriptedServer server([&](int fd, const std::atomic<bool>&) {
    request = test::ScriptedServer::readRequest(fd);
    test::ScriptedServer::sendAll(fd, "HTTP/1.1 200 OK\r\nNtrip-Version: Ntrip/2.0\r\nContent-Type: gnss/data\r\n"
                                      "Transfer-Encoding: chunked\r\n\r\n");
    std::mt19937 random(7);
    std::size_t pos = 0;
    while (pos < recording.size()) {
      const std::size_t n = std::min<std::size_t>(recording.size() - pos, 1 + random() % 3000);
      char size_line[32];
      std::snprintf(size_line, sizeof(size_line), "%zx%s\r\n", n, pos == 0 ? ";ext=1" : "");
      test::ScriptedServer::sendAll(fd, size_line + recording.substr(pos, n) + "\r\n");
      pos += n;
    }
    test::ScriptedServer::sendAll(fd, "0\r\n\r\n");
    std::this_thread::sleep_for(300ms);
  });
  NtripClientSource client(ntripOptions(server.port(), "MSM7", "secret", 2));
  std::optional<ByteSourceError> error;
  const std::string received = readBytes(client, recording.size() + 1, 5s, &error);
  EXPECT_TRUE(client.chunked());
  EXPECT_TRUE(received == recording) << received.size() << " of " << recording.size();
  ASSERT_TRUE(error.has_value());  // the last chunk ends the stream
  EXPECT_EQ(error->kind, ByteSourceErrorKind::ConnectionLost);
  EXPECT_NE(request.find("GET /MSM7 HTTP/1.1\r\n"), std::string::npos) << request;
  EXPECT_NE(request.find("Ntrip-Version: Ntrip/2.0\r\n"), std::string::npos) << request;
  EXPECT_NE(request.find("Authorization: " + basicAuthorization("rover", "secret") + "\r\n"), std::string::npos);
}

TEST(ScriptedCaster, NotFoundIsUnknownMountpoint) {
  test::ScriptedServer server([](int fd, const std::atomic<bool>&) {
    test::ScriptedServer::readRequest(fd);
    test::ScriptedServer::sendAll(fd, "HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\n\r\n");
  });
  NtripClientSource client(ntripOptions(server.port(), "GONE", "secret", 2));
  std::uint8_t buffer[64];
  const ByteSourceRead got = client.read(buffer, sizeof(buffer), 2000ms);
  ASSERT_EQ(got.status, ByteSourceStatus::Error);
  EXPECT_EQ(got.error->kind, ByteSourceErrorKind::UnknownMountpoint) << got.error->describe();
}

TEST(ScriptedCaster, StallIsDetectedCountedAndReconnected) {
  // Accepts, answers ICY 200 OK, then sends nothing.
  test::ScriptedServer server([](int fd, const std::atomic<bool>& stop) {
    test::ScriptedServer::readRequest(fd);
    test::ScriptedServer::sendAll(fd, "ICY 200 OK\r\n");
    for (int i = 0; i < 40 && !stop; ++i) std::this_thread::sleep_for(50ms);
  });
  auto options = ntripOptions(server.port(), "MSM7", "secret", 1);
  options.stall_timeout = 300ms;
  ReconnectingByteSource source([options] { return std::make_unique<NtripClientSource>(options); }, 50ms, 100ms);
  const auto start = Clock::now();
  std::optional<ByteSourceError> error;
  readBytes(source, 1, 3s, &error);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->kind, ByteSourceErrorKind::Stalled) << error->describe();
  const double waited_s = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_GE(waited_s, 0.29);
  EXPECT_LT(waited_s, 2.0);
  readBytes(source, 1, 1500ms);  // it reconnects, and stalls again
  EXPECT_GE(source.counters().stalls, 2u);
  EXPECT_GE(source.counters().reconnects, 1u);
  EXPECT_GE(server.accepted(), 2);
}

TEST(ScriptedCaster, TcpStallIsDetected) {
  test::ScriptedServer server([](int, const std::atomic<bool>& stop) {
    for (int i = 0; i < 20 && !stop; ++i) std::this_thread::sleep_for(50ms);
  });
  TcpClientSource source("127.0.0.1", server.port(), 1000ms, 250ms);
  std::optional<ByteSourceError> error;
  readBytes(source, 1, 2s, &error);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->kind, ByteSourceErrorKind::Stalled);
  EXPECT_EQ(source.counters().stalls, 1u);
}

TEST(ScriptedCaster, GgaIsSentUpstreamPeriodically) {
  std::string upstream;
  test::ScriptedServer server([&](int fd, const std::atomic<bool>& stop) {
    test::ScriptedServer::readRequest(fd);
    test::ScriptedServer::sendAll(fd, "ICY 200 OK\r\n");
    const auto until = Clock::now() + 1200ms;
    while (!stop && Clock::now() < until) {
      test::ScriptedServer::sendAll(fd, std::string(1, '\xD3'));  // keep the stream alive
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 50) > 0) {
        char buffer[512];
        const ssize_t n = ::recv(fd, buffer, sizeof(buffer), 0);
        if (n > 0) upstream.append(buffer, static_cast<std::size_t>(n));
      }
    }
  });
  const ByteSourceSpec spec = parseByteSourceSpec("ntrip://rover:secret@127.0.0.1:" + std::to_string(server.port()) +
                                                  "/NEAREST?version=1&gga_period_s=0.4&lat=55.5&lon=8.25&h=20");
  auto source = openSingleByteSource(spec);
  readBytes(*source, 1000000, 1000ms);
  source->close();
  std::this_thread::sleep_for(300ms);
  // Sent at 0, 0.4, 0.8 s.
  std::size_t count = 0;
  for (std::size_t pos = upstream.find("$GPGGA"); pos != std::string::npos; pos = upstream.find("$GPGGA", pos + 1)) {
    const std::size_t end = upstream.find("\r\n", pos);
    ASSERT_NE(end, std::string::npos);
    const std::string sentence = upstream.substr(pos, end - pos);
    EXPECT_NE(sentence.find(",5530.00000,N,00815.00000,E,1,"), std::string::npos) << sentence;
    EXPECT_EQ(std::stoi(sentence.substr(sentence.size() - 2), nullptr, 16), nmeaChecksum(sentence)) << sentence;
    ++count;
  }
  EXPECT_GE(count, 2u);
  EXPECT_LE(count, 4u);
  EXPECT_EQ(source->counters().gga_sent, count);
}

// ---------------------------------------------------------------------------
// Serial port: a kernel pseudo-terminal pair (the pair socat would make)
// ---------------------------------------------------------------------------

TEST(SerialPort, PtyRecordingWithGarbageGivesTheSameFrames) {
  REQUIRE_STREAMS();
  const std::string recording = readFileBytes(dataPath("streams/rtcm/msm7.rtcm"));
  StreamCounters original_counters;
  const auto original = rtcmFrames(recording, &original_counters);
  ASSERT_GT(original.size(), 100u);

  // Garbage (no 0xD3, not '$') after every 10th frame, 37 bytes each.
  std::string line;
  std::size_t injected = 0, frame_count = 0;
  {
    Rtcm3Framer framer;
    std::uint64_t copied = 0;
    framer.feed(reinterpret_cast<const std::uint8_t*>(recording.data()), recording.size(), [&](const Rtcm3Frame& f) {
      const std::uint64_t end = f.byte_offset + f.payload.size() + 6;
      line += recording.substr(copied, end - copied);
      copied = end;
      if (++frame_count % 10 == 0) {
        line += std::string(37, '\x55');
        injected += 37;
      }
    });
    line += recording.substr(copied);
  }

  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(::grantpt(master), 0);
  ASSERT_EQ(::unlockpt(master), 0);
  const std::string slave = ::ptsname(master);
  SerialPortSource serial(slave, 115200);
  std::uint8_t buffer[4096];
  ASSERT_EQ(serial.read(buffer, sizeof(buffer), 10ms).status, ByteSourceStatus::Timeout);  // opened, raw
  ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);

  std::string received;
  std::size_t written = 0;
  const auto until = Clock::now() + 20s;
  while (received.size() < line.size() && Clock::now() < until) {
    if (written < line.size()) {
      const ssize_t n = ::write(master, line.data() + written, std::min<std::size_t>(1024, line.size() - written));
      if (n > 0) written += static_cast<std::size_t>(n);
    }
    const ByteSourceRead got = serial.read(buffer, sizeof(buffer), 20ms);
    ASSERT_NE(got.status, ByteSourceStatus::Error) << got.error->describe();
    if (got.status == ByteSourceStatus::Data) received.append(reinterpret_cast<const char*>(buffer), got.size);
  }
  ::close(master);
  EXPECT_TRUE(received == line) << received.size() << " of " << line.size() << " bytes";
  StreamCounters counters;
  const auto frames = rtcmFrames(received, &counters);
  EXPECT_EQ(frames, original);
  EXPECT_EQ(counters.garbage_bytes, original_counters.garbage_bytes + injected);
  EXPECT_GE(counters.count(StreamProblemKind::Garbage), original_counters.count(StreamProblemKind::Garbage) + frame_count / 10);
  // The other end closed: a hang-up, reported as a lost connection.
  const ByteSourceRead after = serial.read(buffer, sizeof(buffer), 200ms);
  EXPECT_EQ(after.status, ByteSourceStatus::Error);
}

TEST(SerialPort, MissingDeviceIsOpenFailed) {
  SerialPortSource serial("/dev/ppp_no_such_tty", 115200);
  std::uint8_t buffer[16];
  const ByteSourceRead got = serial.read(buffer, sizeof(buffer), 10ms);
  ASSERT_EQ(got.status, ByteSourceStatus::Error);
  EXPECT_EQ(got.error->kind, ByteSourceErrorKind::OpenFailed);
  EXPECT_NE(got.error->detail.find("/dev/ppp_no_such_tty"), std::string::npos);
}

// ---------------------------------------------------------------------------
// File replay
// ---------------------------------------------------------------------------

TEST(FileReplay, PacedByRawxEpochTimes) {
  REQUIRE_STREAMS();
  const std::string path = dataPath("streams/ubx/gnss_1730.ubx");
  // The epoch span from the UBX observation reader (not the replay's own time reading).
  UbxObservationSource reader(path);
  ObsEpoch epoch;
  std::optional<GnssTime> first, last;
  while (reader.next(epoch) == ObservationRead::Epoch) {
    if (!first) first = epoch.time;
    last = epoch.time;
  }
  ASSERT_TRUE(first && last);
  const double span_s = *last - *first;
  ASSERT_GT(span_s, 60.0);
  const double speed = 50.0;

  FileReplaySource replay(path, speed, 11520.0);
  const auto start = Clock::now();
  const std::string bytes = readBytes(replay, std::string::npos, 30s);
  const double elapsed_s = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_TRUE(bytes == readFileBytes(path));
  EXPECT_EQ(replay.format(), StreamFormat::Ubx);
  EXPECT_GT(replay.timedFrames(), 0u);
  EXPECT_GE(elapsed_s, 0.97 * span_s / speed) << "span " << span_s << " s";
  EXPECT_LE(elapsed_s, span_s / speed + 1.0) << "span " << span_s << " s";
}

TEST(FileReplay, MsmPacingAndByteRateWithoutTimes) {
  REQUIRE_STREAMS();
  // msm7.rtcm: 1 Hz MSM epochs; clk.rtcm: SSR only (no epoch times in our sense): byte rate.
  const std::string msm = dataPath("streams/rtcm/msm7.rtcm");
  FileReplaySource replay(msm, 0.0, 1.0);  // speed 0: as fast as read
  auto start = Clock::now();
  EXPECT_TRUE(readBytes(replay, std::string::npos, 10s) == readFileBytes(msm));
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 1.0);

  const std::string clk = dataPath("streams/rtcm/clk.rtcm");
  const double size = static_cast<double>(readFileBytes(clk).size());
  auto source = openByteSource(parseByteSourceSpec("file://" + clk + "?speed=2&byte_rate=100000"));
  start = Clock::now();
  EXPECT_TRUE(readBytes(*source, std::string::npos, 20s) == readFileBytes(clk));
  const double elapsed_s = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_GE(elapsed_s, 0.9 * size / 200000.0);
  EXPECT_LE(elapsed_s, size / 200000.0 + 0.5);
}

TEST(FileReplay, MissingFileIsOpenFailed) {
  FileReplaySource replay("/nonexistent/x.rtcm3", 1.0, 1000.0);
  std::uint8_t buffer[16];
  const ByteSourceRead got = replay.read(buffer, sizeof(buffer), 10ms);
  ASSERT_EQ(got.status, ByteSourceStatus::Error);
  EXPECT_EQ(got.error->kind, ByteSourceErrorKind::OpenFailed);
  EXPECT_NE(got.error->detail.find("/nonexistent/x.rtcm3"), std::string::npos);
  // Said once, then the end of the recording: a reader loop stops instead of
  // spinning on the same error (ppp_stream_record, the live input).
  EXPECT_EQ(replay.read(buffer, sizeof(buffer), 10ms).status, ByteSourceStatus::Closed);
  EXPECT_EQ(replay.read(buffer, sizeof(buffer), 10ms).status, ByteSourceStatus::Closed);
  EXPECT_EQ(replay.counters().errors(ByteSourceErrorKind::OpenFailed), 1u);
  // close() tries again (and fails again, once).
  replay.close();
  EXPECT_EQ(replay.read(buffer, sizeof(buffer), 10ms).status, ByteSourceStatus::Error);
  EXPECT_EQ(replay.read(buffer, sizeof(buffer), 10ms).status, ByteSourceStatus::Closed);
}

}  // namespace
}  // namespace ppp
