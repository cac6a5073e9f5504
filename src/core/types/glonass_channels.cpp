#include "ppp_bayes_tree/types/glonass_channels.h"

namespace ppp {

bool GlonassChannels::set(int slot, int channel) {
  if (slot < 1 || slot > kMaxSlot || channel < kMinChannel || channel > kMaxChannel) return false;
  channels_[slot] = channel;
  return true;
}

std::optional<int> GlonassChannels::channel(int slot) const {
  if (slot < 1 || slot > kMaxSlot) return std::nullopt;
  return channels_[slot];
}

int GlonassChannels::size() const {
  int n = 0;
  for (const auto& c : channels_) n += c.has_value() ? 1 : 0;
  return n;
}

void GlonassChannels::fillMissing(const GlonassChannels& other) {
  for (int slot = 1; slot <= kMaxSlot; ++slot)
    if (!channels_[slot]) channels_[slot] = other.channels_[slot];
}

GlonassChannels channelsHeaderFirst(const GlonassChannels& header, const GlonassChannels& configured) {
  GlonassChannels out = header;
  out.fillMissing(configured);
  return out;
}

}  // namespace ppp
