// FramerBase (io/framer_base.h) through its two formats, on real frames: the
// first frames of the RTKLIB test recording gmsd7_20121014.rtcm3 (MSM7 1077
// then 1087) and of the u-blox recording gnss_1730.ubx. Each frame is cut from
// the file by its own length field and its check verified with crc24q /
// ubxChecksum, independently of the search under test. Checked for both
// formats: a stream split at every byte position gives the same frames; garbage
// before and between frames is one problem per run, at the run's first byte;
// a frame with a bad check is one checksum error at its first byte, its bytes
// are skipped and the next frame is found; a stream ending inside a frame is
// one TruncatedFrame at the frame's first byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "test_support.h"

namespace ppp {
namespace {

using Bytes = std::vector<std::uint8_t>;

bool streamsAvailable() { return std::filesystem::is_directory(test::dataPath("streams")); }

#define REQUIRE_STREAMS()                                                                        \
  do {                                                                                           \
    if (!streamsAvailable()) GTEST_SKIP() << "no recordings at " << test::dataPath("streams"); \
  } while (0)

/// A real frame and what the framer must report for it.
struct RealFrame {
  Bytes bytes;
  Bytes payload;
  int message_type = 0;
};

/// Where a format keeps a frame's length, type and check.
struct FrameLayout {
  Bytes sync;                     // the first bytes of every frame
  std::size_t header_bytes = 0;   // sync and header, before the payload
  std::size_t check_bytes = 0;    // after the payload
  std::function<std::size_t(const std::uint8_t* header)> payload_length;
  std::function<int(const Bytes& frame)> message_type;
  std::function<bool(const Bytes& frame)> check_holds;
};

/// RTCM 10403.3 section 4: 0xD3, 10-bit length, payload, CRC-24Q.
FrameLayout rtcmLayout() {
  return {{0xD3}, 3, 3, [](const std::uint8_t* h) { return (std::size_t{h[1] & 0x03u} << 8) | h[2]; },
          [](const Bytes& f) { return (f[3] << 4) | (f[4] >> 4); },
          [](const Bytes& f) {
            const std::size_t n = f.size() - 3;
            return crc24q(f.data(), n) == ((std::uint32_t{f[n]} << 16) | (std::uint32_t{f[n + 1]} << 8) | f[n + 2]);
          }};
}

/// UBX-18010854 section 3.2: 0xB5 0x62, class, id, length U2, payload, CK_A CK_B.
FrameLayout ubxLayout() {
  return {{0xB5, 0x62}, 6, 2, [](const std::uint8_t* h) { return h[4] | (std::size_t{h[5]} << 8); },
          [](const Bytes& f) { return (f[2] << 8) | f[3]; },
          [](const Bytes& f) {
            const UbxChecksum ck = ubxChecksum(f.data() + 2, f.size() - 4);
            return ck.a == f[f.size() - 2] && ck.b == f[f.size() - 1];
          }};
}

/// The first `count` frames of a file that starts with a frame, each cut by its
/// own length field and its check verified.
std::vector<RealFrame> firstFrames(const std::string& path, std::size_t count, const FrameLayout& layout) {
  const std::string text = test::readFileBytes(path);
  const Bytes file(text.begin(), text.end());
  std::vector<RealFrame> frames;
  std::size_t pos = 0;
  while (frames.size() < count && pos + layout.header_bytes <= file.size()) {
    EXPECT_TRUE(std::equal(layout.sync.begin(), layout.sync.end(), file.begin() + pos)) << "no sync at byte " << pos;
    const std::size_t length = layout.payload_length(file.data() + pos);
    RealFrame f;
    f.bytes.assign(file.begin() + pos, file.begin() + pos + layout.header_bytes + length + layout.check_bytes);
    f.payload.assign(f.bytes.begin() + layout.header_bytes, f.bytes.end() - layout.check_bytes);
    f.message_type = layout.message_type(f.bytes);
    EXPECT_TRUE(layout.check_holds(f.bytes)) << "frame at byte " << pos;
    pos += f.bytes.size();
    frames.push_back(std::move(f));
  }
  EXPECT_EQ(frames.size(), count) << path;
  return frames;
}

/// What a framer delivered: payload, type, offset and index of each frame.
struct Delivered {
  Bytes payload;
  int message_type = 0;
  std::uint64_t byte_offset = 0;
  std::uint64_t frame_index = 0;
};

/// Feeds `parts` (consecutive pieces of one stream) in turn, then finishes.
template <class Framer>
std::vector<Delivered> feedParts(Framer& framer, const std::vector<Bytes>& parts) {
  std::vector<Delivered> out;
  for (const Bytes& part : parts) {
    framer.feed(part.data(), part.size(), [&](const auto& f) {
      if constexpr (std::is_same_v<Framer, Rtcm3Framer>) {
        out.push_back({f.payload, f.message_type, f.byte_offset, f.frame_index});
      } else {
        out.push_back({f.payload, f.messageType(), f.byte_offset, f.frame_index});
      }
    });
  }
  framer.finish();
  return out;
}

/// `stream` cut into pieces of `chunk` bytes (the last one shorter).
std::vector<Bytes> chunked(const Bytes& stream, std::size_t chunk) {
  std::vector<Bytes> parts;
  for (std::size_t i = 0; i < stream.size(); i += chunk)
    parts.emplace_back(stream.begin() + i, stream.begin() + std::min(stream.size(), i + chunk));
  return parts;
}

Bytes concat(const std::vector<Bytes>& pieces) {
  Bytes out;
  for (const Bytes& p : pieces) out.insert(out.end(), p.begin(), p.end());
  return out;
}

template <class Framer>
void expectSameFramesAtEverySplit(const std::vector<RealFrame>& frames) {
  ASSERT_EQ(frames.size(), 2u);
  const Bytes stream = concat({frames[0].bytes, frames[1].bytes});
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    Framer framer;
    const auto got = feedParts(framer, {Bytes(stream.begin(), stream.begin() + split),
                                        Bytes(stream.begin() + split, stream.end())});
    ASSERT_EQ(got.size(), 2u) << "split at byte " << split;
    std::uint64_t offset = 0;
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(got[i].payload, frames[i].payload) << "split at byte " << split;
      EXPECT_EQ(got[i].message_type, frames[i].message_type) << "split at byte " << split;
      EXPECT_EQ(got[i].byte_offset, offset) << "split at byte " << split;
      EXPECT_EQ(got[i].frame_index, i) << "split at byte " << split;
      offset += frames[i].bytes.size();
    }
    EXPECT_EQ(framer.counters().totalProblems(), 0u) << "split at byte " << split;
    EXPECT_EQ(framer.counters().bytes, stream.size());
    EXPECT_EQ(framer.counters().frames, 2u);
    std::map<int, std::uint64_t> by_type;
    for (const RealFrame& f : frames) ++by_type[f.message_type];
    EXPECT_EQ(framer.counters().frames_by_type, by_type);
  }
}

/// Garbage runs of 5 and 7 bytes before and between two frames, fed whole and
/// byte by byte: two Garbage problems at the runs' first bytes, with the number
/// of good frames before each; the frames at their offsets after the garbage.
template <class Framer>
void expectGarbageCountedAtItsOffsets(const std::vector<RealFrame>& frames, const Bytes& before, const Bytes& between) {
  ASSERT_EQ(frames.size(), 2u);
  const Bytes stream = concat({before, frames[0].bytes, between, frames[1].bytes});
  for (std::size_t chunk : {std::size_t{1}, stream.size()}) {
    Framer framer;
    const auto got = feedParts(framer, chunked(stream, chunk));
    ASSERT_EQ(got.size(), 2u) << "chunk " << chunk;
    EXPECT_EQ(got[0].byte_offset, before.size());
    EXPECT_EQ(got[1].byte_offset, before.size() + frames[0].bytes.size() + between.size());
    EXPECT_EQ(got[0].payload, frames[0].payload);
    EXPECT_EQ(got[1].payload, frames[1].payload);
    EXPECT_EQ(got[1].frame_index, 1u);
    const StreamCounters& c = framer.counters();
    EXPECT_EQ(c.garbage_bytes, before.size() + between.size()) << "chunk " << chunk;
    EXPECT_EQ(c.count(StreamProblemKind::Garbage), 2u) << "chunk " << chunk;
    EXPECT_EQ(c.totalProblems(), 2u) << "chunk " << chunk;
    ASSERT_EQ(c.problems.size(), 2u);
    EXPECT_EQ(c.problems[0].kind, StreamProblemKind::Garbage);
    EXPECT_EQ(c.problems[0].byte_offset, 0u);
    EXPECT_EQ(c.problems[0].frame_index, 0u);
    EXPECT_EQ(c.problems[1].kind, StreamProblemKind::Garbage);
    EXPECT_EQ(c.problems[1].byte_offset, before.size() + frames[0].bytes.size());
    EXPECT_EQ(c.problems[1].frame_index, 1u);
  }
}

/// Frame 0 with one payload bit flipped, then frame 1: a checksum error at
/// byte 0 naming frame 0's type, frame 0's bytes skipped as one garbage run from
/// byte 0, and frame 1 found right after (resynchronisation), in any chunking.
template <class Framer>
void expectChecksumErrorThenResync(const std::vector<RealFrame>& frames, std::size_t payload_start) {
  ASSERT_EQ(frames.size(), 2u);
  Bytes bad = frames[0].bytes;
  bad[payload_start + 10] ^= 0x10;
  const Bytes stream = concat({bad, frames[1].bytes});
  for (std::size_t chunk : {std::size_t{1}, std::size_t{13}, stream.size()}) {
    Framer framer;
    const auto got = feedParts(framer, chunked(stream, chunk));
    ASSERT_EQ(got.size(), 1u) << "chunk " << chunk;
    EXPECT_EQ(got[0].payload, frames[1].payload);
    EXPECT_EQ(got[0].byte_offset, bad.size());
    EXPECT_EQ(got[0].frame_index, 0u);
    const StreamCounters& c = framer.counters();
    EXPECT_EQ(c.count(StreamProblemKind::ChecksumError), 1u) << "chunk " << chunk;
    ASSERT_GE(c.problems.size(), 2u);
    EXPECT_EQ(c.problems[0].kind, StreamProblemKind::ChecksumError);
    EXPECT_EQ(c.problems[0].byte_offset, 0u);
    EXPECT_EQ(c.problems[0].frame_index, 0u);
    EXPECT_EQ(c.problems[0].message_type, frames[0].message_type);
    EXPECT_EQ(c.problems[1].kind, StreamProblemKind::Garbage);
    EXPECT_EQ(c.problems[1].byte_offset, 0u);
    EXPECT_EQ(c.garbage_bytes, bad.size()) << "chunk " << chunk;
    EXPECT_EQ(c.frames, 1u);
  }
}

/// Frame 0 whole, then frame 1 without its last byte.
template <class Framer>
void expectTruncatedFrameAtItsStart(const std::vector<RealFrame>& frames) {
  ASSERT_EQ(frames.size(), 2u);
  Bytes stream = concat({frames[0].bytes, frames[1].bytes});
  stream.pop_back();
  Framer framer;
  const auto got = feedParts(framer, {stream});
  ASSERT_EQ(got.size(), 1u);
  const StreamCounters& c = framer.counters();
  EXPECT_EQ(c.totalProblems(), 1u);
  ASSERT_EQ(c.problems.size(), 1u);
  EXPECT_EQ(c.problems[0].kind, StreamProblemKind::TruncatedFrame);
  EXPECT_EQ(c.problems[0].byte_offset, frames[0].bytes.size());
  EXPECT_EQ(c.problems[0].frame_index, 1u);
  EXPECT_NE(c.problems[0].detail.find(std::to_string(frames[1].bytes.size() - 1) + " byte(s)"), std::string::npos)
      << c.problems[0].detail;
  EXPECT_EQ(c.garbage_bytes, 0u);
}

std::vector<RealFrame> rtcmFrames() {
  return firstFrames(test::dataPath("streams/rtcm/gmsd7_20121014.rtcm3"), 2, rtcmLayout());
}
std::vector<RealFrame> ubxFrames() { return firstFrames(test::dataPath("streams/ubx/gnss_1730.ubx"), 2, ubxLayout()); }

// Garbage without a sync byte, and garbage holding a false sync: RTCM 0xD3 with
// reserved bits set, UBX 0xB5 not followed by 0x62.
const Bytes kRtcmGarbageBefore = {0x00, 0x11, 0x22, 0x33, 0x44};
const Bytes kRtcmGarbageBetween = {0x01, 0xD3, 0xFC, 0x02, 0x03, 0x04, 0x05};
const Bytes kUbxGarbageBefore = {0x00, 0x11, 0x22, 0x33, 0x44};
const Bytes kUbxGarbageBetween = {0x01, 0xB5, 0x61, 0x02, 0x03, 0x04, 0x05};

TEST(FramerBase, RtcmFramesSplitAtEveryBytePosition) {
  REQUIRE_STREAMS();
  const auto frames = rtcmFrames();
  ASSERT_EQ(frames.size(), 2u);
  ASSERT_EQ(frames[0].message_type, 1077);  // README: MSM7 GPS first, then GLONASS
  ASSERT_EQ(frames[1].message_type, 1087);
  expectSameFramesAtEverySplit<Rtcm3Framer>(frames);
}

TEST(FramerBase, UbxFramesSplitAtEveryBytePosition) {
  REQUIRE_STREAMS();
  const auto frames = ubxFrames();
  ASSERT_EQ(frames.size(), 2u);
  ASSERT_EQ(frames[0].message_type, 0x0215);  // RXM-RAWX
  expectSameFramesAtEverySplit<UbxFramer>(frames);
}

TEST(FramerBase, RtcmGarbageBeforeAndBetweenFramesCountedAtItsOffsets) {
  REQUIRE_STREAMS();
  expectGarbageCountedAtItsOffsets<Rtcm3Framer>(rtcmFrames(), kRtcmGarbageBefore, kRtcmGarbageBetween);
}

TEST(FramerBase, UbxGarbageBeforeAndBetweenFramesCountedAtItsOffsets) {
  REQUIRE_STREAMS();
  expectGarbageCountedAtItsOffsets<UbxFramer>(ubxFrames(), kUbxGarbageBefore, kUbxGarbageBetween);
}

TEST(FramerBase, RtcmCrcErrorThenResynchronisation) {
  REQUIRE_STREAMS();
  expectChecksumErrorThenResync<Rtcm3Framer>(rtcmFrames(), 3);
}

TEST(FramerBase, UbxChecksumErrorThenResynchronisation) {
  REQUIRE_STREAMS();
  expectChecksumErrorThenResync<UbxFramer>(ubxFrames(), 6);
}

TEST(FramerBase, RtcmStreamEndingInsideAFrame) {
  REQUIRE_STREAMS();
  expectTruncatedFrameAtItsStart<Rtcm3Framer>(rtcmFrames());
}

TEST(FramerBase, UbxStreamEndingInsideAFrame) {
  REQUIRE_STREAMS();
  expectTruncatedFrameAtItsStart<UbxFramer>(ubxFrames());
}

}  // namespace
}  // namespace ppp
