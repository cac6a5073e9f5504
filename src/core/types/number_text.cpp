#include "ppp_bayes_tree/types/number_text.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace ppp {

std::string fixedDecimals(double value, int decimals) {
  std::ostringstream os;
  os.precision(decimals);
  os << std::fixed << value;
  return os.str();
}

std::string csvNumber(const char* printf_format, double value) {
  if (!std::isfinite(value)) return {};
  char buf[64];
  std::snprintf(buf, sizeof buf, printf_format, value);
  return buf;
}

}  // namespace ppp
