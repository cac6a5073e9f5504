#include "ppp_bayes_tree/io/line_source.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "ppp_bayes_tree/io/parse_error.h"

namespace ppp {

namespace {
constexpr std::size_t kChunk = 256 * 1024;

/// File backend: zlib's gz* functions read gzip and, transparently, plain files.
class GzFileLineSource final : public LineSource {
 public:
  GzFileLineSource(gzFile file, std::string name) : LineSource(std::move(name)), file_(file) {
    gzbuffer(file_, kChunk);
  }
  ~GzFileLineSource() override { gzclose(file_); }
  std::size_t bytesRead() const override {
    const z_off_t off = gzoffset(file_);
    return off < 0 ? 0 : static_cast<std::size_t>(off);
  }
  bool compressed() const override { return gzdirect(file_) == 0; }

 protected:
  std::size_t readBytes(char* buffer, std::size_t capacity) override {
    const int n = gzread(file_, buffer, static_cast<unsigned>(capacity));
    if (n < 0) {
      int code = 0;
      stream_error_ = std::string("corrupt compressed data: ") + gzerror(file_, &code);
      return 0;
    }
    if (n == 0) {
      int code = Z_OK;
      const char* msg = gzerror(file_, &code);
      if (code != Z_OK && code != Z_STREAM_END) {
        stream_error_ = std::string("truncated or corrupt compressed data: ") + msg;
      }
    }
    return static_cast<std::size_t>(n);
  }

 private:
  gzFile file_;
};

/// Memory backend: raw bytes, or gzip members inflated on the fly.
class MemoryLineSource final : public LineSource {
 public:
  MemoryLineSource(std::string bytes, std::string name)
      : LineSource(std::move(name)), data_(std::move(bytes)) {
    gzip_ = looksGzip(reinterpret_cast<const unsigned char*>(data_.data()), data_.size());
    if (gzip_) {
      std::memset(&stream_, 0, sizeof(stream_));
      if (inflateInit2(&stream_, 15 + 16) != Z_OK) {
        stream_error_ = "cannot initialise gzip decoder";
        done_ = true;
      } else {
        inflating_ = true;
        stream_.next_in = reinterpret_cast<Bytef*>(data_.data());
        stream_.avail_in = static_cast<uInt>(data_.size());
      }
    }
  }
  ~MemoryLineSource() override {
    if (inflating_) inflateEnd(&stream_);
  }
  std::size_t bytesRead() const override { return gzip_ ? data_.size() - stream_.avail_in : pos_; }
  bool compressed() const override { return gzip_; }

 protected:
  std::size_t readBytes(char* buffer, std::size_t capacity) override {
    if (done_) return 0;
    if (!gzip_) {
      const std::size_t n = std::min(capacity, data_.size() - pos_);
      std::memcpy(buffer, data_.data() + pos_, n);
      pos_ += n;
      if (n == 0) done_ = true;
      return n;
    }
    stream_.next_out = reinterpret_cast<Bytef*>(buffer);
    stream_.avail_out = static_cast<uInt>(capacity);
    while (stream_.avail_out > 0) {
      if (stream_.avail_in == 0) {
        if (!member_ended_) stream_error_ = "truncated compressed data: unexpected end of gzip stream";
        done_ = true;
        break;
      }
      member_ended_ = false;
      const int rc = inflate(&stream_, Z_NO_FLUSH);
      if (rc == Z_STREAM_END) {
        member_ended_ = true;
        // Another gzip member may follow (concatenated .gz); anything else ends it.
        if (stream_.avail_in >= 2 && looksGzip(stream_.next_in, stream_.avail_in)) {
          inflateReset(&stream_);
          continue;
        }
        done_ = true;
        break;
      }
      if (rc != Z_OK) {
        stream_error_ = std::string("corrupt compressed data: ") +
                        (stream_.msg ? stream_.msg : "inflate error");
        done_ = true;
        break;
      }
    }
    return capacity - stream_.avail_out;
  }

 private:
  std::string data_;
  std::size_t pos_ = 0;
  bool gzip_ = false;
  bool inflating_ = false;
  bool done_ = false;
  bool member_ended_ = false;
  z_stream stream_{};
};
}  // namespace

bool looksGzip(const unsigned char* data, std::size_t size) {
  return size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
}

bool LineSource::fillBuffer() {
  if (eof_) return false;
  // Keep the unread tail, then append a new chunk.
  buffer_.erase(0, buffer_pos_);
  buffer_pos_ = 0;
  const std::size_t old = buffer_.size();
  buffer_.resize(old + kChunk);
  const std::size_t n = readBytes(buffer_.data() + old, kChunk);
  buffer_.resize(old + n);
  if (n == 0) eof_ = true;
  return n > 0;
}

bool LineSource::next(std::string& line) {
  if (pushed_back_) {
    line = std::move(*pushed_back_);
    pushed_back_.reset();
    ++line_number_;
    return true;
  }
  line.clear();
  bool overlong = false;
  while (true) {
    const char* begin = buffer_.data() + buffer_pos_;
    const std::size_t avail = buffer_.size() - buffer_pos_;
    const void* nl = std::memchr(begin, '\n', avail);
    if (nl != nullptr) {
      const std::size_t len = static_cast<const char*>(nl) - begin;
      if (!overlong) line.append(begin, std::min(len, kMaxLineLength - line.size()));
      buffer_pos_ += len + 1;
      break;
    }
    if (!overlong) {
      line.append(begin, std::min(avail, kMaxLineLength - line.size()));
      if (line.size() >= kMaxLineLength) overlong = true;
    }
    buffer_pos_ = buffer_.size();
    if (!fillBuffer()) {
      if (line.empty() && !overlong) return false;
      break;  // last line without a newline
    }
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (overlong) ++overlong_lines_;
  ++line_number_;
  return true;
}

void LineSource::unread(std::string line) {
  pushed_back_ = std::move(line);
  --line_number_;
}

std::unique_ptr<LineSource> openLineSource(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw FileOpenError(path + ": cannot open: is a directory, not a file");
  gzFile f = gzopen(path.c_str(), "rb");
  if (f == nullptr) {
    throw FileOpenError(path + ": cannot open: " + std::strerror(errno));
  }
  return std::make_unique<GzFileLineSource>(f, path);
}

std::string fileBaseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string overlongLinesProblem(std::size_t count) {
  return std::to_string(count) + " line(s) longer than " + std::to_string(LineSource::kMaxLineLength / 1024) +
         " KiB cut and not read: a broken or binary file?";
}

std::unique_ptr<LineSource> memoryLineSource(std::string bytes, std::string name) {
  return std::make_unique<MemoryLineSource>(std::move(bytes), std::move(name));
}

}  // namespace ppp
