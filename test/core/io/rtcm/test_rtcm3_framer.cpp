// Rtcm3Framer / BitReader / BitWriter: framing in any chunking, CRC-24Q,
// resynchronisation after garbage and false preambles, truncation.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/bit_reader.h"
#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "test_support.h"

namespace ppp {
namespace {
using test::sharedDataAvailable;
using test::dataPath;
using test::readFileBytes;

std::vector<std::uint8_t> payloadOfType(int type, std::size_t size, std::uint8_t fill) {
  BitWriter writer;
  writer.putUnsigned(static_cast<std::uint64_t>(type), 12);
  std::vector<std::uint8_t> payload = writer.bytes();
  payload.resize(size, fill);
  payload[1] = static_cast<std::uint8_t>((payload[1] & 0xF0u) | (fill & 0x0Fu));
  return payload;
}

std::vector<Rtcm3Frame> frameAll(const std::vector<std::uint8_t>& bytes, std::size_t chunk, Rtcm3Framer& framer) {
  std::vector<Rtcm3Frame> frames;
  for (std::size_t i = 0; i < bytes.size(); i += chunk) {
    framer.feed(bytes.data() + i, std::min(chunk, bytes.size() - i),
                [&](const Rtcm3Frame& f) { frames.push_back(f); });
  }
  framer.finish();
  return frames;
}

TEST(Crc24q, CatalogueCheckValue) {
  // CRC-24/LTE-A (= Qualcomm CRC-24Q: poly 0x864CFB, init 0, no reflection, no
  // final xor), check value over "123456789" from Greg Cook's CRC catalogue.
  const char* text = "123456789";
  EXPECT_EQ(crc24q(reinterpret_cast<const std::uint8_t*>(text), std::strlen(text)), 0xCDE703u);
}

TEST(BitReaderWriter, RoundTripMixedFields) {
  std::mt19937_64 rng(7);
  struct Field { int bits; int kind; std::int64_t value; };
  std::vector<Field> fields;
  BitWriter writer;
  for (int i = 0; i < 2000; ++i) {
    Field f{1 + static_cast<int>(rng() % 64), static_cast<int>(rng() % 3), 0};
    if (f.kind == 0) {
      const std::uint64_t v = f.bits == 64 ? rng() : rng() & ((std::uint64_t{1} << f.bits) - 1);
      f.value = static_cast<std::int64_t>(v);
      writer.putUnsigned(v, f.bits);
    } else if (f.kind == 1) {
      const std::int64_t half = f.bits == 64 ? INT64_MAX : (std::int64_t{1} << (f.bits - 1));
      f.value = f.bits == 64 ? static_cast<std::int64_t>(rng()) : static_cast<std::int64_t>(rng() % (2 * static_cast<std::uint64_t>(half))) - half;
      writer.putSigned(f.value, f.bits);
    } else {
      if (f.bits < 2) f.bits = 2;
      const std::uint64_t max = f.bits >= 64 ? INT64_MAX : (std::uint64_t{1} << (f.bits - 1)) - 1;
      f.value = static_cast<std::int64_t>(rng() % (max == INT64_MAX ? max : max + 1)) * ((rng() & 1u) ? -1 : 1);
      writer.putSignMagnitude(f.value, f.bits);
    }
    fields.push_back(f);
  }
  BitReader reader(writer.bytes().data(), writer.bytes().size());
  for (const Field& f : fields) {
    const std::int64_t got = f.kind == 0 ? static_cast<std::int64_t>(reader.u(f.bits))
                                         : f.kind == 1 ? reader.s(f.bits) : reader.sm(f.bits);
    ASSERT_EQ(got, f.value) << "bits " << f.bits << " kind " << f.kind;
  }
  EXPECT_TRUE(reader.ok());
  reader.u(static_cast<int>(reader.remainingBits()) + 1);
  EXPECT_TRUE(reader.overrun());
}

TEST(BitWriter, RefusesValuesThatDoNotFit) {
  BitWriter writer;
  EXPECT_THROW(writer.putUnsigned(8, 3), std::out_of_range);
  EXPECT_THROW(writer.putSigned(4, 3), std::out_of_range);
  EXPECT_NO_THROW(writer.putSigned(-4, 3));
  EXPECT_THROW(writer.putSignMagnitude(-4, 3), std::out_of_range);
}

TEST(Rtcm3Framer, SameFramesInAnyChunking) {
  std::vector<std::uint8_t> stream;
  std::vector<std::vector<std::uint8_t>> payloads;
  for (int i = 0; i < 40; ++i) {
    payloads.push_back(payloadOfType(1000 + i, 2 + static_cast<std::size_t>(i * 25 % 1022), static_cast<std::uint8_t>(i)));
    const auto frame = encodeRtcm3Frame(payloads.back());
    stream.insert(stream.end(), frame.begin(), frame.end());
  }
  for (std::size_t chunk : {std::size_t{1}, std::size_t{2}, std::size_t{7}, std::size_t{1000}, stream.size()}) {
    Rtcm3Framer framer;
    const auto frames = frameAll(stream, chunk, framer);
    ASSERT_EQ(frames.size(), payloads.size()) << "chunk " << chunk;
    std::uint64_t offset = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      EXPECT_EQ(frames[i].payload, payloads[i]);
      EXPECT_EQ(frames[i].message_type, 1000 + static_cast<int>(i));
      EXPECT_EQ(frames[i].byte_offset, offset);
      EXPECT_EQ(frames[i].frame_index, i);
      offset += payloads[i].size() + 6;
    }
    EXPECT_EQ(framer.counters().totalProblems(), 0u);
    EXPECT_EQ(framer.counters().bytes, stream.size());
  }
}

TEST(Rtcm3Framer, ResynchronisesAfterGarbageCrcErrorAndFalsePreamble) {
  const auto a = encodeRtcm3Frame(payloadOfType(1005, 19, 0x11));
  auto b = encodeRtcm3Frame(payloadOfType(1077, 200, 0x22));
  const auto c = encodeRtcm3Frame(payloadOfType(1019, 61, 0x33));
  b[50] ^= 0x04;  // one flipped bit: CRC error
  std::vector<std::uint8_t> stream = {0x00, 0xD3, 0x00, 0x05, 0x41};  // garbage with a false preamble
  stream.insert(stream.end(), a.begin(), a.end());
  const std::uint64_t offset_b = stream.size();
  stream.insert(stream.end(), b.begin(), b.end());
  const std::uint64_t offset_c = stream.size();
  stream.insert(stream.end(), c.begin(), c.end());
  stream.insert(stream.end(), c.begin(), c.begin() + 30);  // truncated at the end

  Rtcm3Framer framer;
  const auto frames = frameAll(stream, 3, framer);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].message_type, 1005);
  EXPECT_EQ(frames[0].byte_offset, 5u);
  EXPECT_EQ(frames[1].message_type, 1019);
  EXPECT_EQ(frames[1].byte_offset, offset_c);
  const StreamCounters& n = framer.counters();
  // Two CRC failures: the false preamble at byte 1 reads as a 5-byte frame, and
  // the damaged frame. Neither hides frame a or c.
  EXPECT_EQ(n.count(StreamProblemKind::ChecksumError), 2u);
  EXPECT_EQ(n.count(StreamProblemKind::TruncatedFrame), 1u);
  EXPECT_GE(n.count(StreamProblemKind::Garbage), 2u);  // the leading bytes and the damaged frame's bytes
  bool crc_at_b = false;
  for (const StreamProblem& p : n.problems) {
    if (p.kind == StreamProblemKind::ChecksumError && p.byte_offset == offset_b) {
      crc_at_b = true;
      EXPECT_EQ(p.message_type, 1077);
      EXPECT_NE(p.describe().find("byte " + std::to_string(offset_b)), std::string::npos);
    }
  }
  EXPECT_TRUE(crc_at_b);
  EXPECT_EQ(n.garbage_bytes + 6 + 19 + 6 + 61 + 30, stream.size());
}

TEST(Rtcm3Framer, RealRecordingsFrameWithoutCrcErrors) {
  if (!sharedDataAvailable()) GTEST_SKIP() << "no ../shared/data (set PPP_SHARED_DATA)";
  for (const char* name : {"rtcm/clk.rtcm", "rtcm/msm7.rtcm", "rtcm/week-rollover-STR24.rtcm3",
                           "ssr/SSRA03IGS0_2026188140760_3epoch.rtcm3"}) {
    const std::string bytes = readFileBytes(dataPath(std::string("streams/") + name));
    Rtcm3Framer framer;
    std::uint64_t payload_bytes = 0;
    framer.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
                [&](const Rtcm3Frame& f) { payload_bytes += f.payload.size() + 6; });
    framer.finish();
    SCOPED_TRACE(name);
    EXPECT_EQ(framer.counters().count(StreamProblemKind::ChecksumError), 0u);
    EXPECT_GT(framer.counters().frames, 10u);
    // Every byte is in a good frame or counted as garbage (these files end on a frame).
    EXPECT_EQ(framer.counters().count(StreamProblemKind::TruncatedFrame), 0u);
    EXPECT_EQ(payload_bytes + framer.counters().garbage_bytes, bytes.size());
  }
}

}  // namespace
}  // namespace ppp
