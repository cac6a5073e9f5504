#include "ppp_bayes_tree/io/fixed_width.h"

#include <charconv>
#include <cmath>

namespace ppp {

std::string_view column(std::string_view line, std::size_t start, std::size_t width) {
  if (start >= line.size()) return {};
  return line.substr(start, width);
}

std::string_view trim(std::string_view text) {
  std::size_t b = 0, e = text.size();
  while (b < e && (text[b] == ' ' || text[b] == '\t')) ++b;
  while (e > b && (text[e - 1] == ' ' || text[e - 1] == '\t')) --e;
  return text.substr(b, e - b);
}

bool isBlank(std::string_view text) { return trim(text).empty(); }

std::vector<std::string> splitCsvFields(std::string_view line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      out.emplace_back(trim(cur));
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  out.emplace_back(trim(cur));
  return out;
}

FieldStatus parseDouble(std::string_view field, double& value) {
  std::string_view t = trim(field);
  if (t.empty()) return FieldStatus::Blank;
  char buf[64];
  if (t.size() >= sizeof(buf)) return FieldStatus::Malformed;
  std::size_t n = 0;
  for (char c : t) buf[n++] = (c == 'D' || c == 'd') ? 'e' : c;
  const char* begin = buf;
  if (*begin == '+') ++begin;  // from_chars rejects a leading '+'
  const auto res = std::from_chars(begin, buf + n, value);
  if (res.ec != std::errc() || res.ptr != buf + n || !std::isfinite(value)) {
    return FieldStatus::Malformed;
  }
  return FieldStatus::Ok;
}

FieldStatus parseInt(std::string_view field, long long& value) {
  std::string_view t = trim(field);
  if (t.empty()) return FieldStatus::Blank;
  if (t.front() == '+') t.remove_prefix(1);
  const auto res = std::from_chars(t.data(), t.data() + t.size(), value);
  if (res.ec != std::errc() || res.ptr != t.data() + t.size()) return FieldStatus::Malformed;
  return FieldStatus::Ok;
}

std::optional<double> toDouble(std::string_view field) {
  double v = 0;
  if (parseDouble(field, v) != FieldStatus::Ok) return std::nullopt;
  return v;
}

std::optional<long long> toInt(std::string_view field) {
  long long v = 0;
  if (parseInt(field, v) != FieldStatus::Ok) return std::nullopt;
  return v;
}

}  // namespace ppp
