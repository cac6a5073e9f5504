#pragma once
// RINEX 3 observation codes ("C1C", "L2W", "S5Q"): observable type, frequency
// band number and tracking attribute (RINEX 3.05, section 5.1 and table A23).
#include <optional>
#include <string>
#include <string_view>

namespace ppp {

enum class ObservableType : char {
  Pseudorange = 'C',
  CarrierPhase = 'L',
  Doppler = 'D',
  SignalStrength = 'S',
  Ionosphere = 'I',   // RINEX 3 'I' (ionosphere phase delay), rarely used
  ChannelNumber = 'X',
};

struct ObservationCode {
  ObservableType type = ObservableType::Pseudorange;
  char band = '1';       // '1'..'9' (RINEX band number)
  char attribute = 'C';  // tracking mode / channel: C, P, W, Y, L, S, X, Q, I, ...

  /// Parses a 3-character RINEX 3 code (or 2-character "C1", "L2" with attribute ' ').
  static std::optional<ObservationCode> parse(std::string_view text);
  std::string toString() const;
  /// The signal part without the type, e.g. "1C" for "C1C".
  std::string signal() const { return std::string{band, attribute}; }

  friend bool operator==(const ObservationCode& a, const ObservationCode& b) {
    return a.type == b.type && a.band == b.band && a.attribute == b.attribute;
  }
  friend bool operator!=(const ObservationCode& a, const ObservationCode& b) { return !(a == b); }
  friend bool operator<(const ObservationCode& a, const ObservationCode& b) {
    if (a.type != b.type) return a.type < b.type;
    if (a.band != b.band) return a.band < b.band;
    return a.attribute < b.attribute;
  }
};

}  // namespace ppp
