#include "ppp_bayes_tree/io/transport/credential_mask.h"

namespace ppp {
namespace {

bool isBreak(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\'' || c == '"'; }

/// Start of the authority that ends at `at`: after the last "//", blank or quote before it.
std::size_t authorityStart(const std::string& text, std::size_t at) {
  std::size_t start = 0;
  for (std::size_t i = 0; i < at; ++i) {
    if (isBreak(text[i])) start = i + 1;
    else if (text[i] == '/' && i + 1 < at && text[i + 1] == '/') start = i + 2;
  }
  return start;
}

/// The ':' that separates user and password in text[start, at): the first one that is
/// not a scheme's "name:/" (as in "ntrip:/user:pass@").
std::size_t passwordColon(const std::string& text, std::size_t start, std::size_t at) {
  for (std::size_t i = start; i < at; ++i) {
    if (text[i] != ':') continue;
    if (i + 1 < at && text[i + 1] == '/') {  // "scheme:/...": the password colon comes later, if any
      const std::size_t later = text.find(':', i + 1);
      if (later != std::string::npos && later < at) return later;
      return i;  // "ntrip:/user@": everything up to '@' hidden
    }
    return i;
  }
  return std::string::npos;
}

}  // namespace

std::string maskCredentials(const std::string& text) {
  std::string out;
  std::size_t done = 0;  // text[0, done) is in out
  std::size_t pos = 0;
  while (pos < text.size()) {
    // The end of this token: the next blank or quote.
    std::size_t end = pos;
    while (end < text.size() && !isBreak(text[end])) ++end;
    // The authority's '@': the last '@' of the token before the host part, that is
    // before the first '/' that follows an '@' (a mountpoint or path).
    std::size_t at = std::string::npos;
    for (std::size_t i = pos; i < end; ++i) {
      if (text[i] == '@') at = i;
      else if (text[i] == '/' && at != std::string::npos && i > at) break;
    }
    if (at != std::string::npos) {
      const std::size_t start = std::max(pos, authorityStart(text, at));
      const std::size_t colon = passwordColon(text, start, at);
      if (colon != std::string::npos) {
        out.append(text, done, colon + 1 - done);
        out += "***";
        done = at;
      }
    }
    pos = end + 1;
  }
  if (done < text.size()) out.append(text, done, std::string::npos);
  return out;
}

}  // namespace ppp
