#pragma once
// StreamPump: reads a recorded byte stream (RTCM 3, UBX) from an open file in
// chunks and hands each chunk to a decoder, the same way for every reader of
// stream files:
//
//   read a chunk -> feed(chunk) -> drain()    while the file has bytes
//   at the end of the file      -> finish() -> drain()    once
//
// `drain` takes what the decoder produced (epochs, ephemerides) after every
// chunk and once more after finish(). A read error is not an end of the file:
// it throws FileOpenError naming the file, the byte offset and the system's
// reason, and finish() is not called.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace ppp {

/// What the pump does with the bytes: the decoder's three calls.
struct StreamPumpSteps {
  std::function<void(const std::uint8_t* data, std::size_t size)> feed;
  std::function<void()> finish;  // the file ended
  std::function<void()> drain;   // after every feed and after finish (may be empty)
};

class StreamPump {
 public:
  static constexpr std::size_t kDefaultChunkBytes = std::size_t{1} << 16;

  /// Reads `file` (open for binary reading, not owned); `path` names it in errors.
  StreamPump(std::FILE* file, std::string path, std::size_t chunk_bytes = kDefaultChunkBytes);

  /// One chunk: feed and drain; at the end of the file, finish and drain.
  /// Does nothing once finished.
  void step(const StreamPumpSteps& steps);
  /// step() until the end of the file; returns the bytes read.
  std::uint64_t run(const StreamPumpSteps& steps);

  bool finished() const { return finished_; }
  std::uint64_t bytesRead() const { return bytes_read_; }

 private:
  std::FILE* file_;
  std::string path_;
  std::vector<std::uint8_t> chunk_;
  std::uint64_t bytes_read_ = 0;
  bool finished_ = false;
};

}  // namespace ppp
