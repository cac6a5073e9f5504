// StreamPump (io/stream_pump.h): feed/drain per chunk, finish and drain once at
// the end of the file, on files made here (a file of whole chunks, a file
// shorter than a chunk, an empty file), a read error (a directory opened for
// reading: fread fails with EISDIR), and a real recording read through the pump
// by the RTCM observation source.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/stream_pump.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "test_support.h"

namespace ppp {
namespace {

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

File openForReading(const std::string& path) { return File(std::fopen(path.c_str(), "rb"), &std::fclose); }

/// The calls the pump made, in order: "feed N", "finish", "drain".
struct Recorder {
  std::vector<std::string> calls;
  std::vector<std::uint8_t> bytes;
  StreamPumpSteps steps() {
    return {[this](const std::uint8_t* data, std::size_t size) {
              calls.push_back("feed " + std::to_string(size));
              bytes.insert(bytes.end(), data, data + size);
            },
            [this]() { calls.push_back("finish"); }, [this]() { calls.push_back("drain"); }};
  }
  std::uint64_t bytes_read = 0;  // what run() returned
  bool finished = false;
};

/// Opens `path` and pumps it to its end in chunks of `chunk` bytes.
Recorder pumpWhole(const std::string& path, std::size_t chunk) {
  File f = openForReading(path);
  Recorder r;
  StreamPump pump(f.get(), path, chunk);
  r.bytes_read = pump.run(r.steps());
  r.finished = pump.finished();
  return r;
}

std::vector<std::uint8_t> countingBytes(std::size_t n) {
  std::vector<std::uint8_t> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(i * 7 + 1);
  return out;
}

class StreamPumpTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::tempDir("stream_pump"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::vector<std::uint8_t>& bytes) {
    const std::string path = (dir_ / name).string();
    test::writeFileBytes(path, bytes);
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(StreamPumpTest, WholeChunksThenEndOfFile) {
  const auto data = countingBytes(8);
  const Recorder r = pumpWhole(write("eight.bin", data), 4);
  EXPECT_EQ(r.bytes_read, 8u);
  EXPECT_TRUE(r.finished);
  // The end is found by a read that returns nothing: no empty feed.
  EXPECT_EQ(r.calls, (std::vector<std::string>{"feed 4", "drain", "feed 4", "drain", "finish", "drain"}));
  EXPECT_EQ(r.bytes, data);
}

TEST_F(StreamPumpTest, AFileShorterThanOneChunk) {
  const auto data = countingBytes(3);
  const std::string path = write("three.bin", data);
  for (std::size_t chunk : {std::size_t{4}, StreamPump::kDefaultChunkBytes}) {
    const Recorder r = pumpWhole(path, chunk);
    EXPECT_EQ(r.bytes_read, 3u);
    EXPECT_EQ(r.calls, (std::vector<std::string>{"feed 3", "drain", "finish", "drain"})) << "chunk " << chunk;
    EXPECT_EQ(r.bytes, data);
  }
}

TEST_F(StreamPumpTest, AnEmptyFileIsFinishedAndDrainedOnce) {
  const Recorder r = pumpWhole(write("empty.bin", {}), StreamPump::kDefaultChunkBytes);
  EXPECT_EQ(r.bytes_read, 0u);
  EXPECT_EQ(r.calls, (std::vector<std::string>{"finish", "drain"}));
}

TEST_F(StreamPumpTest, StepByStepAndNothingAfterTheEnd) {
  const auto data = countingBytes(5);
  const std::string path = write("five.bin", data);
  File f = openForReading(path);
  Recorder r;
  StreamPump pump(f.get(), path, 4);
  pump.step(r.steps());
  EXPECT_FALSE(pump.finished());
  EXPECT_EQ(pump.bytesRead(), 4u);
  pump.step(r.steps());
  pump.step(r.steps());
  EXPECT_TRUE(pump.finished());
  pump.step(r.steps());  // finished: nothing more
  EXPECT_EQ(r.calls, (std::vector<std::string>{"feed 4", "drain", "feed 1", "drain", "finish", "drain"}));
}

TEST_F(StreamPumpTest, AReadErrorNamesTheFileAndIsNotAnEndOfStream) {
  const std::string path = dir_.string();  // a directory: fopen succeeds, fread fails (EISDIR)
  File f = openForReading(path);
  ASSERT_TRUE(f) << "fopen of a directory failed on this system";
  Recorder r;
  StreamPump pump(f.get(), path);
  try {
    pump.run(r.steps());
    FAIL() << "a read error ended the stream silently";
  } catch (const FileOpenError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("at byte 0"), std::string::npos) << what;
    EXPECT_NE(what.find("directory"), std::string::npos) << what;  // strerror(EISDIR)
  }
  EXPECT_TRUE(r.calls.empty());  // neither finish nor drain: the decoder's end is not reached
  EXPECT_FALSE(pump.finished());
}

TEST_F(StreamPumpTest, StreamFileReadersReportAReadErrorNamingTheFile) {
  // Both observation sources read the whole file once in their constructor.
  for (const auto& open : {+[](const std::string& p) { RtcmObservationSource source(p); },
                           +[](const std::string& p) { UbxObservationSource source(p); }}) {
    try {
      open(dir_.string());
      FAIL() << "a directory read as an empty stream";
    } catch (const FileOpenError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("cannot read " + dir_.string()), std::string::npos) << what;
    }
  }
}

TEST(StreamPump, ARealRecordingReadThroughThePumpInAnyChunkSize) {
  const std::string path = test::dataPath("streams/rtcm/gmsd7_20121014.rtcm3");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no recording at " << path;
  const std::string whole = test::readFileBytes(path);
  for (std::size_t chunk : {std::size_t{1000}, std::size_t{65536}, std::size_t{1} << 20}) {
    const Recorder r = pumpWhole(path, chunk);
    EXPECT_EQ(r.bytes_read, whole.size());
    EXPECT_EQ(std::string(r.bytes.begin(), r.bytes.end()), whole);
    EXPECT_EQ(r.calls.size(), 2 * ((whole.size() + chunk - 1) / chunk) + 2) << "chunk " << chunk;
  }
}

}  // namespace
}  // namespace ppp
