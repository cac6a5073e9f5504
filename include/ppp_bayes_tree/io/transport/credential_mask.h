#pragma once
// maskCredentials: the one function every message that may hold an input spec goes
// through before it is logged, shown in diagnostics or thrown. It hides the password
// of every "user:password@host" in the text, whatever else is wrong with the text:
// any scheme or letter case (ntrip://, NTRIP://, ntrip:/, no scheme at all), leading
// blanks, unescaped '?', '/', '@' or ':' in the password, several specs in one line.
//
// Rule: for each '@' that is followed by a host (the last '@' before the next blank,
// quote, '/' or end), the authority starts after the last "//" or blank or quote
// before it (else at the text's start); if it holds a ':' beyond a scheme's
// "name:/", everything from that ':' up to the '@' is replaced by ":***". A text
// without '@' is returned unchanged (a spec without userinfo carries no password).
#include <string>

namespace ppp {

/// `text` with the password part of every userinfo replaced by "***" (see above).
std::string maskCredentials(const std::string& text);

}  // namespace ppp
