#pragma once
// StreamEpoch: an observation epoch decoded from a receiver stream, the form both
// receiver formats give (RTCM 3 MSM: io/rtcm/rtcm3_decoder.h; u-blox RXM-RAWX:
// io/ubx/ubx_observation_source.h). io/rinex/stream_epoch_layout.h lays it out
// along a RINEX observation header.
#include <cstdint>
#include <optional>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// One tracked signal of a satellite in a decoded stream epoch.
struct StreamSignal {
  char band = '1';       // RINEX band number
  char attribute = 'C';  // RINEX tracking attribute
  std::optional<double> pseudorange_m;
  std::optional<double> carrier_phase_cycles;
  std::optional<double> doppler_hz;
  std::optional<double> cnr_dbhz;
  std::uint8_t lli = 0;           // RINEX LLI: bit 0 loss of lock, bit 1 half-cycle ambiguity
  double lock_time_s = 0.0;       // minimum lock time from the indicator
};

struct StreamSatellite {
  SatelliteId satellite;
  std::vector<StreamSignal> signals;
};

/// An observation epoch decoded from a receiver stream (GPST).
struct StreamEpoch {
  GnssTime time;
  std::vector<StreamSatellite> satellites;
  std::uint64_t byte_offset = 0;  // of the first message of the epoch
  std::uint64_t frame_index = 0;
};

}  // namespace ppp
