#pragma once
// format(): printf-style formatting into a std::string of the length the text
// needs, never cut at a fixed buffer size. The one formatting helper of the
// library: reports, file writers and problem texts call it instead of keeping
// their own snprintf into a local buffer. The compiler checks the arguments
// against the format (GCC/Clang `format` attribute), as it does for printf.
#include <cstdarg>
#include <string>

namespace ppp {

#if defined(__GNUC__) || defined(__clang__)
#define PPP_PRINTF_FORMAT(format_index, first_argument) \
  __attribute__((format(printf, format_index, first_argument)))
#else
#define PPP_PRINTF_FORMAT(format_index, first_argument)
#endif

/// The text printf would write for `printf_format` and the arguments, whole.
std::string format(const char* printf_format, ...) PPP_PRINTF_FORMAT(1, 2);

/// The same for an argument list already started (va_start) by the caller.
std::string formatList(const char* printf_format, std::va_list arguments) PPP_PRINTF_FORMAT(1, 0);

}  // namespace ppp
