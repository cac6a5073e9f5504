#include "ppp_bayes_tree/types/observation_code.h"

namespace ppp {

std::optional<ObservationCode> ObservationCode::parse(std::string_view text) {
  if (text.size() != 2 && text.size() != 3) return std::nullopt;
  ObservationCode code;
  switch (text[0]) {
    case 'C': code.type = ObservableType::Pseudorange; break;
    case 'L': code.type = ObservableType::CarrierPhase; break;
    case 'D': code.type = ObservableType::Doppler; break;
    case 'S': code.type = ObservableType::SignalStrength; break;
    case 'I': code.type = ObservableType::Ionosphere; break;
    case 'X': code.type = ObservableType::ChannelNumber; break;
    default: return std::nullopt;
  }
  if (text[1] < '1' || text[1] > '9') return std::nullopt;
  code.band = text[1];
  if (text.size() == 3) {
    const char a = text[2];
    if (!((a >= 'A' && a <= 'Z') || a == ' ')) return std::nullopt;
    code.attribute = a;
  } else {
    code.attribute = ' ';
  }
  return code;
}

std::string ObservationCode::toString() const {
  std::string s{static_cast<char>(type), band};
  if (attribute != ' ') s.push_back(attribute);
  return s;
}

}  // namespace ppp
