#pragma once
// ReceiverStateLayout: where each named member of the receiver state sits in the
// state vector that the estimators, the factors and the measurement model's
// Jacobian row share:
//   position  (x, y, z) ECEF [m]       3
//   ZWD       zenith wet delay [m]     1
//   clocks    receiver clock c*dt [m]  one per processed GNSS system, in the
//             order of config.signals.systems (each absorbs that system's IF
//             code bias, so GPS and Galileo do not share one clock)
//   gradients north and east horizontal tropospheric gradients G_N, G_E [m]
//             (optional, 2; troposphere_gradient.h)
// With GPS alone the vector is the classic (x, y, z, zwd, clock). A new block
// (e.g. one slant ionosphere per satellite) is added here as a new named range
// after the clocks; nothing else indexes the vector by number.
// The layout is a small value (no allocation), copied with every ReceiverState.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

class ReceiverStateLayout {
 public:
  /// GPS only: the 5-vector (x, y, z, zwd, clock).
  ReceiverStateLayout() : ReceiverStateLayout(std::vector<GnssSystem>{GnssSystem::GPS}) {}
  /// One clock per system, in the given order (duplicates ignored; empty: GPS).
  /// With `troposphere_gradients`, the gradient block (G_N, G_E) follows the clocks.
  explicit ReceiverStateLayout(const std::vector<GnssSystem>& clock_systems, bool troposphere_gradients = false);

  static constexpr int kPositionSize = 3;
  /// Index of the first position component (x); y and z follow.
  int position() const { return 0; }
  int zwd() const { return kPositionSize; }
  /// Index of the system's receiver clock; -1 when the system has no clock.
  int clock(GnssSystem system) const { return clock_index_[static_cast<int>(system)]; }
  bool hasClock(GnssSystem system) const { return clock(system) >= 0; }
  int firstClock() const { return zwd() + 1; }
  int clockCount() const { return clock_count_; }
  /// The systems with a clock, in state order.
  std::vector<GnssSystem> clockSystems() const;
  /// Whether the state carries the horizontal tropospheric gradients.
  bool hasGradients() const { return gradients_; }
  static constexpr int kGradientSize = 2;
  /// Index of the north gradient G_N; the east gradient G_E follows. -1 without gradients.
  int gradientNorth() const { return gradients_ ? firstClock() + clock_count_ : -1; }
  int gradientEast() const { return gradients_ ? gradientNorth() + 1 : -1; }
  /// Dimension of the receiver state vector.
  int dim() const { return firstClock() + clock_count_ + (gradients_ ? kGradientSize : 0); }

  bool isPosition(int index) const { return index >= position() && index < position() + kPositionSize; }
  bool isClock(int index) const { return index >= firstClock() && index < firstClock() + clock_count_; }
  bool isGradient(int index) const {
    return gradients_ && index >= gradientNorth() && index < gradientNorth() + kGradientSize;
  }
  /// The system of the clock at `index` (isClock(index) must hold).
  GnssSystem clockSystem(int index) const { return clock_order_[static_cast<std::size_t>(index - firstClock())]; }
  /// Name of a component for messages: "x", "y", "z", "zwd", "clock G", "gradient N".
  std::string componentName(int index) const;

  bool operator==(const ReceiverStateLayout& o) const {
    return clock_count_ == o.clock_count_ && clock_index_ == o.clock_index_ && gradients_ == o.gradients_;
  }
  bool operator!=(const ReceiverStateLayout& o) const { return !(*this == o); }

 private:
  std::array<std::int8_t, kNumGnssSystems> clock_index_{};
  std::array<GnssSystem, kNumGnssSystems> clock_order_{};
  int clock_count_ = 0;
  bool gradients_ = false;
};

}  // namespace ppp
