#pragma once
// Stream epochs (io/stream_epoch.h) in RINEX terms: the observation types a set of
// stream signals needs in a RINEX header, and a stream epoch laid out along a
// header's type lists as an ObsEpoch. Both receiver formats (RTCM 3, UBX) and the
// live input go through these, the one conversion of all paths.
#include <array>
#include <map>
#include <utility>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/io/stream_epoch.h"
#include "ppp_bayes_tree/types/obs_epoch.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// The RINEX observation types of a set of stream signals per system: for each
/// signal (sorted by band, then attribute) C, L, D, S where present.
struct StreamSignalInventory {
  // per system, per signal "1C": bit 0 C, 1 L, 2 D, 3 S present
  std::array<std::map<std::pair<char, char>, int>, kNumGnssSystems> signals;
  void add(const StreamEpoch& epoch);
  void fillTypes(RinexObsHeader& header) const;
};

/// Copies a stream epoch into an ObsEpoch laid out by the header's types
/// (signals without a type in the header are dropped). The LLI goes with the phase.
void streamEpochToObsEpoch(const StreamEpoch& in, const RinexObsHeader& header, ObsEpoch& out);

}  // namespace ppp
