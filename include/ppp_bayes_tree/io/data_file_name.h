#pragma once
// The one rule for file names taken from data (a RINEX MARKER NAME, a bag's
// station, a configured marker name): such text becomes one file-name component
// that stays inside the output folder it is joined to. Every byte outside
// [A-Za-z0-9._-] becomes '_' (so '/' and '\\' never split a path), leading dots
// become '_' (no hidden files), and an empty text or one of dots only ("." or
// "..") is replaced by the fallback ("station"). "ZIM2" stays "ZIM2"; "N/A"
// becomes "N_A"; "../q" becomes "___q".
#include <string>
#include <string_view>

namespace ppp {

constexpr std::string_view kDataFileNameFallback = "station";

/// `text` as a safe file-name component (see above).
std::string dataFileName(std::string_view text, std::string_view fallback = kDataFileNameFallback);

}  // namespace ppp
