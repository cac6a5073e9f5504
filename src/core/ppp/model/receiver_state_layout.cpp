#include "ppp_bayes_tree/ppp/model/receiver_state_layout.h"

namespace ppp {

ReceiverStateLayout::ReceiverStateLayout(const std::vector<GnssSystem>& clock_systems, bool troposphere_gradients)
    : gradients_(troposphere_gradients) {
  clock_index_.fill(-1);
  for (GnssSystem s : clock_systems) {
    if (hasClock(s)) continue;
    clock_index_[static_cast<int>(s)] = static_cast<std::int8_t>(firstClock() + clock_count_);
    clock_order_[static_cast<std::size_t>(clock_count_)] = s;
    ++clock_count_;
  }
  if (clock_count_ == 0) {
    clock_index_[static_cast<int>(GnssSystem::GPS)] = static_cast<std::int8_t>(firstClock());
    clock_order_[0] = GnssSystem::GPS;
    clock_count_ = 1;
  }
}

std::vector<GnssSystem> ReceiverStateLayout::clockSystems() const {
  return std::vector<GnssSystem>(clock_order_.begin(), clock_order_.begin() + clock_count_);
}

std::string ReceiverStateLayout::componentName(int index) const {
  if (isPosition(index)) return std::string(1, static_cast<char>('x' + (index - position())));
  if (index == zwd()) return "zwd";
  if (isClock(index)) return std::string("clock ") + systemLetter(clockSystem(index));
  if (index == gradientNorth()) return "gradient N";
  if (index == gradientEast()) return "gradient E";
  return "component " + std::to_string(index);
}

}  // namespace ppp
