#pragma once
// Inputs RTKLIB 2.4.3 needs for the peer comparison (scripts/compare_rtklib.sh),
// written from our own readers:
//  * A GPS RINEX 3.04 navigation file whose clock terms come from a precise
//    RINEX clock file. rnx2rtkp needs a broadcast record per satellite even with
//    pos1-sateph=precise: it takes the broadcast clock to compute the signal
//    transmission time. One record per satellite and hour (toc = toe = the full
//    hour): af0, af1 from a least-squares line through the precise clock samples
//    within +-15 min of the hour (at least two), af2 = 0; IODE = IODC = hour of
//    the week modulo 256 (RTKLIB's uniqnav() drops records of one satellite with
//    equal IODE); health 0; a nominal circular-ish GPS orbit, which RTKLIB does
//    not use for positions in precise mode (RINEX 3.05 table A6 layout).
//  * A GPS-only SP3-c file: RTKLIB 2.4.3 reads the SP3 satellite count with two
//    digits, so an SP3-d file listing more than 99 satellites loses records.
//    Positions, clocks and epochs are copied from the SP3 reader (GPST, "%c G"
//    line "GPS"); absent values are written as the SP3 bad-value markers.
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"

namespace ppp {

struct ClockNavigationSummary {
  std::string text;             // the whole RINEX navigation file
  std::size_t records = 0;
  std::size_t satellites = 0;
};
ClockNavigationSummary gpsNavigationFromClocks(const std::vector<const RinexClockFile*>& clocks);

struct GpsSp3Summary {
  std::string text;  // the whole SP3-c file
  std::size_t epochs = 0;
  std::size_t satellites = 0;
};
GpsSp3Summary gpsOnlySp3(const Sp3File& sp3);
/// The same writer for the satellites of `systems` ("%c M" when not GPS only;
/// the simulator's products with Galileo). gpsOnlySp3 = sp3Copy(sp3, {GPS}).
GpsSp3Summary sp3Copy(const Sp3File& sp3, const std::vector<GnssSystem>& systems);

}  // namespace ppp
