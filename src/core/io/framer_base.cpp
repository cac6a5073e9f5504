#include "ppp_bayes_tree/io/framer_base.h"

namespace ppp {

void FramerBase::feedBytes(const std::uint8_t* data, std::size_t size,
                           const std::function<void(const FrameBytes&)>& on_frame) {
  counters_.bytes += size;
  buffer_.insert(buffer_.end(), data, data + size);
  scan(on_frame);
}

void FramerBase::scan(const std::function<void(const FrameBytes&)>& on_frame) {
  std::size_t pos = 0;
  auto skipByte = [&]() {
    skipped_.skip(buffer_offset_ + pos, buffer_[pos]);
    ++pos;
  };
  bool wait = false;
  while (pos < buffer_.size() && !wait) {
    const FrameCandidate candidate = examine(buffer_.data() + pos, buffer_.size() - pos);
    switch (candidate.verdict) {
      case FrameCandidate::Verdict::NotAFrame:
        skipByte();
        break;
      case FrameCandidate::Verdict::NeedMoreBytes:
        wait = true;
        break;
      case FrameCandidate::Verdict::Rejected:
        skipped_.flush(counters_);
        counters_.add(StreamProblem{candidate.fault.kind, buffer_offset_ + pos, counters_.frames,
                                    candidate.fault.message_type, candidate.fault.detail});
        skipByte();  // resynchronise from the byte after the false sync
        break;
      case FrameCandidate::Verdict::Good: {
        skipped_.flush(counters_);
        const FrameBytes frame{buffer_.data() + pos, candidate.frame_bytes, candidate.message_type,
                               buffer_offset_ + pos, counters_.frames};
        ++counters_.frames;
        ++counters_.frames_by_type[candidate.message_type];
        pos += candidate.frame_bytes;
        on_frame(frame);
        break;
      }
    }
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(pos));
  buffer_offset_ += pos;
}

void FramerBase::finish() {
  if (!buffer_.empty()) {
    skipped_.flush(counters_);
    if (const auto fault = truncatedFrame(buffer_.data(), buffer_.size())) {
      counters_.add(StreamProblem{fault->kind, buffer_offset_, counters_.frames, fault->message_type, fault->detail});
    } else {
      for (std::size_t i = 0; i < buffer_.size(); ++i) skipped_.skip(buffer_offset_ + i, buffer_[i]);
    }
    buffer_offset_ += buffer_.size();
    buffer_.clear();
  }
  skipped_.flush(counters_);
}

}  // namespace ppp
