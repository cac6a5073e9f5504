// rostest, serial end to end into the PPP nodes: a pseudo-terminal pair made
// by socat (pty,raw,echo=0,link=A pty,raw,echo=0,link=B) as the serial line; the test
// writes week-rollover-STR24.rtcm3 into A, with 41 garbage bytes (no RTCM 3 preamble
// 0xD3 among them) after every 25th frame, 4 KiB every 40 ms (a pty has no baud rate:
// 19 min of data in about 13 s; the nodes' subscriber queues hold the whole file,
// test/rostest/live_str24.yaml; their outputs come at about 90 epochs/s). ppp_stream_node (started by the test) reads
// serial://B?baud=115200 and publishes /gnss/receiver for ppp_ekf_node and
// ppp_smoother_node of launch/live.launch (example b). No frame may be lost and each
// node's fixes must equal ppp_solve's on the file (EKF; smoother filtered) at every
// epoch but perhaps the last, to 1 mm; the stream node's diagnostics count exactly the
// garbage written (the file's own 208 bytes before its first frame included: the core
// framer on the written bytes is the reference).
#include <termios.h>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "rostest/live_support.h"

namespace {

// 41 bytes, with a NUL and 0xFF, but no RTCM 3 preamble 0xD3.
const std::string kGarbage("garbage on the line: \x01\x02\xff\x00 0123456789ABCDE", 41);

bool socatAvailable() { return std::system("command -v socat > /dev/null 2>&1") == 0; }

}  // namespace

TEST(LiveSerial, SocatPtyToStreamNodeToBothNodesEqualsPppSolveTo1mm) {
  PPP_REQUIRE_SHARED_DATA();
  if (!socatAvailable()) GTEST_SKIP() << "socat is not installed (Debian package socat)";
  using namespace ppp_ros::test;
  PppSolveBoth offline;
  ASSERT_NO_FATAL_FAILURE(solveStr24Live("live_serial", &offline));

  // The line: the recording with garbage after every 25th frame.
  const std::string recording = ppp::test::readFileBytes(str24Recording());
  std::string line;
  std::size_t frames = 0, injected = 0;
  {
    ppp::Rtcm3Framer framer;
    std::uint64_t copied = 0;
    framer.feed(reinterpret_cast<const std::uint8_t*>(recording.data()), recording.size(),
                [&](const ppp::Rtcm3Frame& f) {
                  const std::uint64_t end = f.byte_offset + f.payload.size() + 6;
                  line += recording.substr(copied, end - copied);
                  copied = end;
                  if (++frames % 25 == 0) {
                    line += kGarbage;
                    injected += kGarbage.size();
                  }
                });
    line += recording.substr(copied);
  }
  ASSERT_GT(frames, 6000u);
  ppp::Rtcm3Framer reference;  // what the stream node's framer must count on these bytes
  std::size_t reference_frames = 0;
  reference.feed(reinterpret_cast<const std::uint8_t*>(line.data()), line.size(),
                 [&](const ppp::Rtcm3Frame&) { ++reference_frames; });
  ASSERT_EQ(reference_frames, frames);
  ASSERT_GE(reference.counters().garbage_bytes, injected);

  const std::filesystem::path dir = ppp::test::tempDir("live_serial");
  const std::string a = (dir / "A").string(), b = (dir / "B").string();
  ChildProcess socat({"socat", "-d", "-d", "pty,raw,echo=0,link=" + a, "pty,raw,echo=0,link=" + b},
                     (dir / "socat.log").string());
  for (int i = 0; i < 100 && !(std::filesystem::exists(a) && std::filesystem::exists(b)); ++i)
    ros::WallDuration(0.05).sleep();
  ASSERT_TRUE(std::filesystem::exists(a) && std::filesystem::exists(b))
      << "socat made no pty pair: " << ppp::test::readFileBytes((dir / "socat.log").string());

  ros::NodeHandle nh;
  LiveLaunchOutputs out;
  out.subscribe(nh);
  StreamNodeDiagnostics stream;
  std::unique_ptr<ChildProcess> node;
  ASSERT_NO_FATAL_FAILURE(startConnectedStreamNode(nh, "serial://" + b + "?baud=115200",
                                                   (dir / "ppp_stream_node.log").string(), stream, &node));

  const int fd = ::open(a.c_str(), O_WRONLY | O_NOCTTY);
  ASSERT_GE(fd, 0) << a;
  termios raw{};
  ASSERT_EQ(::tcgetattr(fd, &raw), 0);
  ::cfmakeraw(&raw);
  ASSERT_EQ(::tcsetattr(fd, TCSANOW, &raw), 0);
  for (std::size_t done = 0; done < line.size();) {
    const ssize_t n = ::write(fd, line.data() + done, std::min<std::size_t>(4096, line.size() - done));
    ASSERT_GT(n, 0) << "write to " << a << " failed at byte " << done;
    done += static_cast<std::size_t>(n);
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
  }
  expectAllFramesPublished(stream, frames);
  waitAndExpectEqualTo(out, offline, "serial (socat pty) -> ppp_stream_node -> /gnss/receiver");
  ::close(fd);
  EXPECT_EQ(stream.value("bytes"), std::to_string(line.size()));
  EXPECT_EQ(stream.value("CRC errors"), "0");
  EXPECT_EQ(stream.value("garbage bytes"), std::to_string(reference.counters().garbage_bytes))
      << injected << " bytes injected";
  std::printf("[ figures  ] ppp_stream_node: %s bytes, %s frames published, %s garbage bytes (%zu injected + %zu "
              "in the file), %s CRC errors\n",
              stream.value("bytes").c_str(), stream.value("frames published").c_str(),
              stream.value("garbage bytes").c_str(), injected,
              static_cast<std::size_t>(reference.counters().garbage_bytes) - injected,
              stream.value("CRC errors").c_str());
}

int main(int argc, char** argv) { return ppp_ros::test::liveRostestMain(argc, argv, "rostest_live_serial"); }
