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
  }
  return "unknown problem";
}

std::string StreamProblem::describe() const {
  std::ostringstream text;
  text << "byte " << byte_offset << " (frame " << frame_index << ")";
  if (message_type != 0) text << ", type " << message_type;
  text << ": " << streamProblemKindName(kind);
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

}  // namespace ppp
