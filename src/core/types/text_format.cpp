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
  // First pass: the length; second pass: the text into a string of that length.
  std::va_list measure;
  va_copy(measure, arguments);
  const int length = std::vsnprintf(nullptr, 0, printf_format, measure);
  va_end(measure);
  if (length < 0) throw std::invalid_argument(std::string("format: cannot format \"") + printf_format + "\"");
  std::string text(static_cast<std::size_t>(length), '\0');
  std::vsnprintf(text.data(), text.size() + 1, printf_format, arguments);
  return text;
}

}  // namespace ppp
