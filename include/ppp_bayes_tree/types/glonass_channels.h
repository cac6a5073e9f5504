#pragma once
// GLONASS FDMA frequency channel numbers per slot, filled from the RINEX 3
// "GLONASS SLOT / FRQ #" header or from GLONASS navigation records.
#include <array>
#include <optional>

namespace ppp {

class GlonassChannels {
 public:
  static constexpr int kMaxSlot = 30;
  /// The channels in use since 2005 (GLONASS ICD edition 5.1, 2008, section 3.3.1.1:
  /// k = -7 ... +6); +7..+13 and the earlier 0..24 are no channel of today's satellites.
  static constexpr int kMinChannel = -7, kMaxChannel = 6;
  /// Sets the channel k (kMinChannel..kMaxChannel) of a slot (1..30); returns false when out of range.
  bool set(int slot, int channel);
  std::optional<int> channel(int slot) const;
  int size() const;  // number of slots with a known channel
  /// Takes the channels of `other` for the slots that have none here.
  void fillMissing(const GlonassChannels& other);

 private:
  std::array<std::optional<int>, kMaxSlot + 1> channels_{};
};

/// The channels a run uses: the observation header's (GLONASS SLOT / FRQ #) for its
/// slots, the configured ones (signals.glonass_channels, with those of the
/// navigation records) for the others. The signal selection takes its frequencies
/// from them, and the run's notes name a satellite's channel from them.
GlonassChannels channelsHeaderFirst(const GlonassChannels& header, const GlonassChannels& configured);

}  // namespace ppp
