#pragma once
// RinexObsWriter: writes a RINEX 3.04 observation file (RINEX 3.04 section 5,
// tables A1-A3) from a RinexObsHeader and ObsEpoch records, whatever produced
// them (RTCM 3 or UBX decoders, a simulation). Values are written %14.3f as
// RINEX prescribes (F14.3), with the LLI digit after carrier phases (blank when
// 0) and the SSI blank. Values that do not fit F14.3 are written blank.
#include <ostream>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

class RinexObsWriter {
 public:
  explicit RinexObsWriter(std::ostream& out) : out_(out) {}
  /// Header: version 3.04, the header's station, receiver, antenna, position,
  /// types per system (the systems with types), first observation, GLONASS
  /// channels, SYS / PHASE SHIFT (zero) and comments.
  void writeHeader(const RinexObsHeader& header);
  /// One epoch; observation k of a satellite is written in the column of the k-th
  /// type of its system (the ObsEpoch convention). Satellites of a system without
  /// types in the header are left out.
  void writeEpoch(const ObsEpoch& epoch, const RinexObsHeader& header);

 private:
  std::ostream& out_;
};

}  // namespace ppp
