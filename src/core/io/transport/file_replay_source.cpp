#include "ppp_bayes_tree/io/transport/file_replay_source.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <thread>

namespace ppp {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kSecondsPerWeek = 604800.0;
constexpr double kMaxEpochJump_s = 60.0;
constexpr std::size_t kReadChunkBytes = 16 * 1024;

std::uint64_t bits(const std::vector<std::uint8_t>& data, std::size_t start, std::size_t count) {
  std::uint64_t value = 0;
  for (std::size_t i = start; i < start + count; ++i) {
    value = (value << 1) | ((data[i / 8] >> (7 - i % 8)) & 1u);
  }
  return value;
}

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

std::optional<double> rtcm3EpochTimeOfWeek_s(const std::vector<std::uint8_t>& payload) {
  if (payload.size() < 8) return std::nullopt;  // 12 + 12 + 30 bits
  const int type = static_cast<int>(bits(payload, 0, 12));
  const bool gps_legacy = type >= 1001 && type <= 1004;
  const bool gps_gal_sbas_qzss_msm = (type >= 1071 && type <= 1077) || (type >= 1091 && type <= 1097) ||
                                     (type >= 1101 && type <= 1107) || (type >= 1111 && type <= 1117);
  const bool bds_msm = type >= 1121 && type <= 1127;
  if (!gps_legacy && !gps_gal_sbas_qzss_msm && !bds_msm) return std::nullopt;
  const double tow_ms = static_cast<double>(bits(payload, 24, 30));
  if (tow_ms >= kSecondsPerWeek * 1000.0) return std::nullopt;
  double tow_s = tow_ms / 1000.0;
  if (bds_msm) tow_s = std::fmod(tow_s + kGpstMinusBdt_s, kSecondsPerWeek);  // BDT -> GPST
  return tow_s;
}

std::optional<double> ubxEpochTimeOfWeek_s(const UbxFrame& frame) {
  if (frame.message_class != 0x02 || frame.message_id != 0x15 || frame.payload.size() < 8) return std::nullopt;
  std::uint64_t raw = 0;
  for (int i = 7; i >= 0; --i) raw = (raw << 8) | frame.payload[static_cast<std::size_t>(i)];
  double tow_s = 0.0;
  std::memcpy(&tow_s, &raw, sizeof(tow_s));
  if (!(tow_s >= 0.0 && tow_s < kSecondsPerWeek)) return std::nullopt;
  return tow_s;
}

FileReplaySource::FileReplaySource(std::string path, double speed, double byte_rate_bytes_per_s,
                                   StreamFormat format)
    : path_(std::move(path)), speed_(speed), byte_rate_(byte_rate_bytes_per_s), format_(format) {}

std::string FileReplaySource::describe() const {
  char speed[32];
  std::snprintf(speed, sizeof(speed), "%g", speed_);
  std::string text = "file://" + path_ + "?speed=" + speed;
  if (format_ != StreamFormat::Unknown) text += " (" + std::string(streamFormatName(format_)) + ")";
  return text;
}

void FileReplaySource::close() {
  file_.close();
  opened_ = false;
  open_failed_ = false;
  eof_ = false;
  rtcm_ = Rtcm3Framer();
  ubx_ = UbxFramer();
  pending_.clear();
  segments_.clear();
  pending_offset_ = read_offset_ = released_end_ = 0;
  anchor_epoch_s_.reset();
  last_epoch_s_.reset();
}

std::optional<ByteSourceError> FileReplaySource::open() {
  std::error_code ec;
  if (std::filesystem::is_directory(path_, ec))  // an ifstream opens a directory and reads nothing
    return ByteSourceError{ByteSourceErrorKind::OpenFailed, path_ + ": is a directory, not a recording"};
  file_.open(path_, std::ios::binary);
  if (!file_) {
    return ByteSourceError{ByteSourceErrorKind::OpenFailed, path_ + ": " + std::strerror(errno)};
  }
  if (format_ == StreamFormat::Unknown) {
    std::vector<std::uint8_t> head(64 * 1024);
    file_.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
    format_ = detectStreamFormat(head.data(), static_cast<std::size_t>(file_.gcount()));
    file_.clear();
    file_.seekg(0);
  }
  opened_ = true;
  start_wall_ = Clock::now();
  last_release_ = start_wall_;
  return std::nullopt;
}

void FileReplaySource::onFrame(std::uint64_t end_offset, std::optional<double> epoch_s) {
  const std::uint64_t begin = segments_.empty() ? released_end_ : segments_.back().end_offset;
  const std::uint64_t size = end_offset > begin ? end_offset - begin : 0;
  Clock::time_point release = last_release_;
  if (speed_ > 0.0) {
    if (epoch_s) {
      ++timed_frames_;
      double epoch = *epoch_s;
      if (anchor_epoch_s_ && epoch < *anchor_epoch_s_ - kSecondsPerWeek / 2) epoch += kSecondsPerWeek;  // week rollover
      const bool jump = last_epoch_s_ && (epoch < *last_epoch_s_ - 0.5 || epoch > *last_epoch_s_ + kMaxEpochJump_s);
      if (!anchor_epoch_s_ || jump) {
        if (jump) ++reanchors_;
        anchor_epoch_s_ = epoch;
        anchor_wall_ = last_release_;
      }
      release = std::max(last_release_, anchor_wall_ + seconds((epoch - *anchor_epoch_s_) / speed_));
      last_epoch_s_ = epoch;
    } else if (!anchor_epoch_s_ && byte_rate_ > 0.0) {
      release = last_release_ + seconds(static_cast<double>(size) / (byte_rate_ * speed_));
    }
  }
  segments_.push_back({end_offset, release});
  last_release_ = release;
}

bool FileReplaySource::readMore() {
  std::uint8_t chunk[kReadChunkBytes];
  file_.read(reinterpret_cast<char*>(chunk), sizeof(chunk));
  const auto got = static_cast<std::size_t>(file_.gcount());
  pending_.insert(pending_.end(), chunk, chunk + got);
  read_offset_ += got;
  if (format_ == StreamFormat::Rtcm3) {
    rtcm_.feed(chunk, got, [&](const Rtcm3Frame& frame) {
      onFrame(frame.byte_offset + frame.payload.size() + 6, rtcm3EpochTimeOfWeek_s(frame.payload));
    });
  } else if (format_ == StreamFormat::Ubx) {
    ubx_.feed(chunk, got, [&](const UbxFrame& frame) {
      onFrame(frame.byte_offset + frame.payload.size() + 8, ubxEpochTimeOfWeek_s(frame));
    });
  } else if (got > 0) {
    onFrame(read_offset_, std::nullopt);
  }
  if (got == 0 || file_.eof()) {
    rtcm_.finish();
    ubx_.finish();
    const std::uint64_t last_end = segments_.empty() ? released_end_ : segments_.back().end_offset;
    if (read_offset_ > last_end) segments_.push_back({read_offset_, last_release_});  // bytes after the last frame
    eof_ = true;
    return false;
  }
  return true;
}

ByteSourceRead FileReplaySource::read(std::uint8_t* buffer, std::size_t capacity,
                                      std::chrono::milliseconds timeout) {
  if (open_failed_) return ByteSourceRead::closed();
  if (!opened_) {
    if (auto error = open()) {
      open_failed_ = true;
      return fail(error->kind, std::move(error->detail));
    }
    ++counters_.connects;
  }
  const auto deadline = Clock::now() + timeout;
  while (true) {
    while (segments_.empty() && !eof_) readMore();
    if (segments_.empty()) return ByteSourceRead::closed();
    const Segment& next = segments_.front();
    const auto now = Clock::now();
    if (next.release <= now) {
      const std::size_t available = static_cast<std::size_t>(next.end_offset - pending_offset_);
      const std::size_t n = std::min(capacity, available);
      std::copy(pending_.begin(), pending_.begin() + static_cast<long>(n), buffer);
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<long>(n));
      pending_offset_ += n;
      released_end_ = pending_offset_;
      if (pending_offset_ >= next.end_offset) segments_.pop_front();
      counters_.bytes += n;
      if (n > 0) return ByteSourceRead::data(n);
      continue;
    }
    if (now >= deadline) return ByteSourceRead::timeout();
    std::this_thread::sleep_until(std::min(deadline, next.release));
  }
}

}  // namespace ppp
