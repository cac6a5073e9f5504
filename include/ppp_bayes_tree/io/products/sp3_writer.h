#pragma once
// SP3-c writer: a copy of the records of some systems of an SP3 file, as read by
// our SP3 reader. RTKLIB 2.4.3 reads the SP3 satellite count with two digits, so
// an SP3-d file listing more than 99 satellites loses records: the peer
// comparison (scripts/compare_rtklib.sh) gives it a GPS-only SP3-c copy, and the
// simulator writes its products with it. Positions, clocks and epochs are copied
// from the SP3 reader (GPST, "%c G" line "GPS" when GPS only, else "%c M");
// absent values are written as the SP3 bad-value markers.
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/sp3_reader.h"

namespace ppp {

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
