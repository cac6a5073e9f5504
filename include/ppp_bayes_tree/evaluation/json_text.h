#pragma once
// Small JSON text helpers for the report writers (statistics, ppp_solve
// summaries, Monte Carlo tables): RFC 8259 string escaping and numbers, with
// non-finite values written as null.
#include <string>
#include <string_view>

namespace ppp {

/// A quoted JSON string: '"' and '\' escaped, control characters as \u00XX.
std::string jsonString(std::string_view text);
/// A JSON number with `significant_digits` (%.Ng), or null when not finite.
std::string jsonNumber(double value, int significant_digits = 9);

}  // namespace ppp
