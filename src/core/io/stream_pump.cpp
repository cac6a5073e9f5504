#include "ppp_bayes_tree/io/stream_pump.h"

#include <cerrno>
#include <cstring>

#include "ppp_bayes_tree/io/parse_error.h"

namespace ppp {

StreamPump::StreamPump(std::FILE* file, std::string path, std::size_t chunk_bytes)
    : file_(file), path_(std::move(path)), chunk_(chunk_bytes == 0 ? kDefaultChunkBytes : chunk_bytes) {}

void StreamPump::step(const StreamPumpSteps& steps) {
  if (finished_) return;
  errno = 0;
  const std::size_t n = std::fread(chunk_.data(), 1, chunk_.size(), file_);
  if (n > 0) {
    bytes_read_ += n;
    steps.feed(chunk_.data(), n);
  } else if (std::ferror(file_)) {
    const int error = errno;
    throw FileOpenError("cannot read " + path_ + " at byte " + std::to_string(bytes_read_) + ": " +
                        (error != 0 ? std::strerror(error) : "read error"));
  } else {
    finished_ = true;
    steps.finish();
  }
  if (steps.drain) steps.drain();
}

std::uint64_t StreamPump::run(const StreamPumpSteps& steps) {
  while (!finished_) step(steps);
  return bytes_read_;
}

}  // namespace ppp
