#pragma once
// printableText: text that came from the network or a file (a caster's status line,
// a chunk-size line, a header field) made safe for a terminal, a log file and a
// diagnostic value before it is shown. Printable ASCII (0x20..0x7e) but '\\' is kept;
// '\\' is written "\\\\", tab/CR/LF "\t" "\r" "\n", every other byte (ESC, other
// controls, DEL, bytes >= 0x80) as "\xHH", so an ANSI escape sequence shows as
// "\x1b[2J" instead of acting on the terminal. Longer texts are cut after
// `max_bytes` input bytes and end in "... (N bytes)".
#include <cstddef>
#include <string_view>
#include <string>

namespace ppp {

constexpr std::size_t kUntrustedTextMaxBytes = 200;

std::string printableText(std::string_view text, std::size_t max_bytes = kUntrustedTextMaxBytes);

}  // namespace ppp
