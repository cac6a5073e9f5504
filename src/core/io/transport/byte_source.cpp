#include "ppp_bayes_tree/io/transport/byte_source.h"

namespace ppp {

std::string_view byteSourceErrorKindName(ByteSourceErrorKind kind) {
  switch (kind) {
    case ByteSourceErrorKind::BadSpec: return "bad input spec";
    case ByteSourceErrorKind::OpenFailed: return "open failed";
    case ByteSourceErrorKind::HostNotFound: return "host not found";
    case ByteSourceErrorKind::ConnectionRefused: return "connection refused";
    case ByteSourceErrorKind::ConnectTimeout: return "connect timeout";
    case ByteSourceErrorKind::ConnectionLost: return "connection lost";
    case ByteSourceErrorKind::AuthenticationRefused: return "authentication refused";
    case ByteSourceErrorKind::UnknownMountpoint: return "unknown mountpoint";
    case ByteSourceErrorKind::ProtocolError: return "protocol error";
    case ByteSourceErrorKind::Stalled: return "stalled";
    case ByteSourceErrorKind::ReadFailed: return "read failed";
    case ByteSourceErrorKind::WriteFailed: return "write failed";
  }
  return "unknown error";
}

bool isPermanentByteSourceError(ByteSourceErrorKind kind) {
  return kind == ByteSourceErrorKind::BadSpec || kind == ByteSourceErrorKind::AuthenticationRefused ||
         kind == ByteSourceErrorKind::UnknownMountpoint;
}

std::string ByteSourceError::describe() const {
  std::string text(byteSourceErrorKindName(kind));
  if (!detail.empty()) text += ": " + detail;
  return text;
}

void ByteSourceCounters::addError(const ByteSourceError& error) {
  ++errors_by_kind[error.kind];
  if (error.kind == ByteSourceErrorKind::Stalled) ++stalls;
  last_error = error;
}

std::uint64_t ByteSourceCounters::errors(ByteSourceErrorKind kind) const {
  const auto it = errors_by_kind.find(kind);
  return it == errors_by_kind.end() ? 0 : it->second;
}

std::uint64_t ByteSourceCounters::totalErrors() const {
  std::uint64_t total = 0;
  for (const auto& [kind, count] : errors_by_kind) total += count;
  return total;
}

ByteSourceRead ByteSource::fail(ByteSourceErrorKind kind, std::string detail) {
  ByteSourceRead result = ByteSourceRead::failure(kind, std::move(detail));
  counters_.addError(*result.error);
  return result;
}

}  // namespace ppp
