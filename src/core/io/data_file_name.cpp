#include "ppp_bayes_tree/io/data_file_name.h"

namespace ppp {
namespace {

bool allowedInFileName(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
         c == '-';
}

}  // namespace

std::string dataFileName(std::string_view text, std::string_view fallback) {
  std::string name;
  name.reserve(text.size());
  for (const char c : text) name += allowedInFileName(c) ? c : '_';
  if (name.find_first_not_of('.') == std::string::npos)  // empty, ".", "..", ...
    return fallback.empty() || fallback == text ? std::string(kDataFileNameFallback) : dataFileName(fallback);
  for (char& c : name) {
    if (c != '.') break;
    c = '_';
  }
  return name;
}

}  // namespace ppp
