#pragma once
// GLONASS FDMA frequency channel numbers per slot, filled from the RINEX 3
// "GLONASS SLOT / FRQ #" header or from GLONASS navigation records.
#include <array>
#include <optional>

namespace ppp {

class GlonassChannels {
 public:
  static constexpr int kMaxSlot = 30;
  /// Sets the channel k (-7..+13) of a slot (1..30); returns false when out of range.
  bool set(int slot, int channel);
  std::optional<int> channel(int slot) const;
  int size() const;  // number of slots with a known channel
  /// Takes the channels of `other` for the slots that have none here.
  void fillMissing(const GlonassChannels& other);

 private:
  std::array<std::optional<int>, kMaxSlot + 1> channels_{};
};

}  // namespace ppp
