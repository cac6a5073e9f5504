#include "ppp_bayes_tree/types/text_format.h"

#include <cstdio>
#include <stdexcept>

namespace ppp {

std::string format(const char* printf_format, ...) {
  std::va_list arguments;
  va_start(arguments, printf_format);
  std::string text;
  try {
    text = formatList(printf_format, arguments);
  } catch (...) {
    va_end(arguments);
    throw;
  }
  va_end(arguments);
  return text;
}

std::string formatList(const char* printf_format, std::va_list arguments) {
  // One pass into a buffer on the stack, which holds most texts (a record, a
  // header line); a longer text is formatted again into a string of its length.
  char buffer[256];
  std::va_list again;
  va_copy(again, arguments);
  const int length = std::vsnprintf(buffer, sizeof buffer, printf_format, arguments);
  if (length < 0) {
    va_end(again);
    throw std::invalid_argument(std::string("format: cannot format \"") + printf_format + "\"");
  }
  if (static_cast<std::size_t>(length) < sizeof buffer) {
    va_end(again);
    return std::string(buffer, static_cast<std::size_t>(length));
  }
  std::string text(static_cast<std::size_t>(length), '\0');
  std::vsnprintf(text.data(), text.size() + 1, printf_format, again);
  va_end(again);
  return text;
}

}  // namespace ppp
