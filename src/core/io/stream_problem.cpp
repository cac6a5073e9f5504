#include "ppp_bayes_tree/io/stream_problem.h"

#include <sstream>

namespace ppp {

std::string_view streamProblemKindName(StreamProblemKind kind) {
  switch (kind) {
    case StreamProblemKind::ChecksumError: return "checksum error";
    case StreamProblemKind::TruncatedFrame: return "truncated frame";
    case StreamProblemKind::Garbage: return "garbage between frames";
    case StreamProblemKind::BadLength: return "bad length";
    case StreamProblemKind::UnknownMessage: return "unknown message type";
    case StreamProblemKind::MalformedMessage: return "malformed message";
    case StreamProblemKind::InconsistentEphemeris: return "inconsistent ephemeris";
    case StreamProblemKind::UnresolvedTime: return "unresolved time";
    case StreamProblemKind::SsrWithoutBroadcast: return "SSR without broadcast record";
    case StreamProblemKind::SsrTooOld: return "SSR older than its validity";
    case StreamProblemKind::EpochTimeRefused: return "epoch time refused";
    case StreamProblemKind::ImplausibleValue: return "implausible value";
  }
  return "unknown problem";
}

std::string streamPlace(std::uint64_t byte_offset, std::uint64_t frame_index, int message_type) {
  std::ostringstream text;
  text << "byte " << byte_offset << " (frame " << frame_index << ")";
  if (message_type != 0) text << ", type " << message_type;
  return text.str();
}

std::string StreamProblem::describe() const {
  std::ostringstream text;
  text << streamPlace(byte_offset, frame_index, message_type) << ": " << streamProblemKindName(kind);
  if (!detail.empty()) text << ": " << detail;
  return text.str();
}

void StreamCounters::add(StreamProblem problem) {
  ++problems_by_kind[problem.kind];
  if (problems.size() < kMaxKeptProblems) problems.push_back(std::move(problem));
}

std::uint64_t StreamCounters::count(StreamProblemKind kind) const {
  const auto it = problems_by_kind.find(kind);
  return it == problems_by_kind.end() ? 0 : it->second;
}

std::uint64_t StreamCounters::totalProblems() const {
  std::uint64_t total = 0;
  for (const auto& [kind, n] : problems_by_kind) total += n;
  return total;
}

std::string StreamCounters::problemLines(std::size_t max_listed) const {
  std::string out;
  for (const auto& [kind, count] : problems_by_kind)
    out += "  " + std::to_string(count) + " x " + std::string(streamProblemKindName(kind)) + "\n";
  for (std::size_t i = 0; i < problems.size() && i < max_listed; ++i) out += "  " + problems[i].describe() + "\n";
  return out;
}

}  // namespace ppp
