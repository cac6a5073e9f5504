#pragma once
// Helpers for the fixed-column formats (RINEX, SP3, ANTEX, SINEX): safe column
// slicing and number parsing that tells "blank" from "malformed".
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ppp {

/// Columns [start, start+width) of a line (0-based); shorter lines give what is
/// there (possibly empty). Never throws.
std::string_view column(std::string_view line, std::size_t start, std::size_t width);
/// The view without leading and trailing blanks.
std::string_view trim(std::string_view text);
/// True when the text is empty or all blanks.
bool isBlank(std::string_view text);

/// The comma-separated fields of a CSV line (no quoting), each trimmed; carriage
/// returns dropped; "a,b," gives three fields, the last empty.
std::vector<std::string> splitCsvFields(std::string_view line);

/// Result of parsing a numeric field.
enum class FieldStatus { Ok, Blank, Malformed };

/// Parses a floating-point field; accepts Fortran 'D'/'d' exponents. Blank gives
/// FieldStatus::Blank; non-finite values are Malformed.
FieldStatus parseDouble(std::string_view field, double& value);
/// Parses an integer field (optional sign, blanks around).
FieldStatus parseInt(std::string_view field, long long& value);

/// Convenience: nullopt when blank or malformed.
std::optional<double> toDouble(std::string_view field);
std::optional<long long> toInt(std::string_view field);

}  // namespace ppp
