#pragma once
// The GPS navigation file RTKLIB 2.4.3 needs for the peer comparison
// (scripts/compare_rtklib.sh, ppp_rtklib_inputs), written from our own readers:
// a GPS RINEX 3.04 navigation file whose clock terms come from a precise RINEX
// clock file. rnx2rtkp needs a broadcast record per satellite even with
// pos1-sateph=precise: it takes the broadcast clock to compute the signal
// transmission time. One record per satellite and hour (toc = toe = the full
// hour): af0, af1 from a least-squares line through the precise clock samples
// within +-15 min of the hour (at least two), af2 = 0; IODE = IODC = hour of the
// week modulo 256 (RTKLIB's uniqnav() drops records of one satellite with equal
// IODE); health 0; a nominal circular-ish GPS orbit, which RTKLIB does not use
// for positions in precise mode (RINEX 3.05 table A6 layout).
// The GPS-only SP3-c copy RTKLIB also needs is io/products/sp3_writer.h.
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"

namespace ppp {

struct ClockNavigationSummary {
  std::string text;             // the whole RINEX navigation file
  std::size_t records = 0;
  std::size_t satellites = 0;
};
ClockNavigationSummary gpsNavigationFromClocks(const std::vector<const RinexClockFile*>& clocks);

}  // namespace ppp
