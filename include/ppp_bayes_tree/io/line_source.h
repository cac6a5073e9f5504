#pragma once
// LineSource: a streaming line reader over a file or an in-memory buffer that
// accepts plain text and gzip alike, detected by content (the 1f 8b magic), not
// by the file name. Lines come without their "\n" / "\r\n". Memory use is one
// buffer, whatever the file size.
#include <cstddef>
#include <memory>
#include <optional>
#include <string>

namespace ppp {

class LineSource {
 public:
  /// Lines longer than this are cut to it (and counted): binary input can never
  /// make a reader allocate without bound.
  static constexpr std::size_t kMaxLineLength = 64 * 1024;

  virtual ~LineSource() = default;

  /// Reads the next line into `line`. Returns false at the end of the data or on
  /// a read error (see streamError()).
  bool next(std::string& line);
  /// Puts `line` back so that the next call to next() returns it again.
  void unread(std::string line);

  /// The name used in messages (the path, or the name given to a buffer).
  const std::string& name() const { return name_; }
  /// 1-based number of the line last returned by next().
  std::size_t lineNumber() const { return line_number_; }
  /// Set when reading stopped on corrupt or truncated compressed data.
  const std::optional<std::string>& streamError() const { return stream_error_; }
  std::size_t overlongLines() const { return overlong_lines_; }
  /// Bytes consumed from the underlying (possibly compressed) data so far.
  virtual std::size_t bytesRead() const = 0;
  /// True when the data is gzip-compressed.
  virtual bool compressed() const = 0;

 protected:
  explicit LineSource(std::string name) : name_(std::move(name)) {}
  /// Fills `buffer` with up to `capacity` decoded bytes; returns the count, 0 at
  /// the end; sets stream_error_ and returns 0 on failure.
  virtual std::size_t readBytes(char* buffer, std::size_t capacity) = 0;
  std::optional<std::string> stream_error_;

 private:
  bool fillBuffer();

  std::string name_;
  std::size_t line_number_ = 0;
  std::size_t overlong_lines_ = 0;
  std::string buffer_;
  std::size_t buffer_pos_ = 0;
  bool eof_ = false;
  std::optional<std::string> pushed_back_;
};

/// Opens a file (plain or gzip). Throws FileOpenError when it cannot be opened.
std::unique_ptr<LineSource> openLineSource(const std::string& path);
/// Wraps a buffer (plain or gzip); `name` is used in messages.
std::unique_ptr<LineSource> memoryLineSource(std::string bytes, std::string name = "<memory>");

/// The file name without its directories ("a/b/c.rnx" -> "c.rnx"), as messages name files.
std::string fileBaseName(const std::string& path);

/// The problem text for lines cut at kMaxLineLength (a broken or binary file:
/// whatever the cut line held is lost, so a reader reports it as a problem).
std::string overlongLinesProblem(std::size_t count);

/// True when the first two bytes are the gzip magic 1f 8b.
bool looksGzip(const unsigned char* data, std::size_t size);

}  // namespace ppp
