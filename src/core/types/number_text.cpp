#include "ppp_bayes_tree/types/number_text.h"

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {

std::string fixedDecimals(double value, int decimals) {
  std::ostringstream os;
  os.precision(decimals);
  os << std::fixed << value;
  return os.str();
}

std::string csvNumber(const char* printf_format, double value) {
  if (!std::isfinite(value)) return {};
  return format(printf_format, value);
}

std::string minutesSecondsText(double seconds) {
  const int t = static_cast<int>(seconds + 0.5);
  return format("%d:%02d", t / 60, t % 60);
}

}  // namespace ppp
