#pragma once
// Numbers as text for reports and CSV files: one place for the small
// formatting helpers every writer and screening message needs.
#include <string>

namespace ppp {

/// `value` with exactly `decimals` digits after the point ("1.234").
std::string fixedDecimals(double value, int decimals = 3);

/// `value` through a printf format with one double conversion ("%.4f"); the
/// empty text for NaN or infinity (a blank CSV field, never "nan").
std::string csvNumber(const char* printf_format, double value);

/// A duration as minutes and seconds, rounded to the second ("12:05"), for progress lines.
std::string minutesSecondsText(double seconds);

}  // namespace ppp
