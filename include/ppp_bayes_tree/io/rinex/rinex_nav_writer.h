#pragma once
// RinexNavWriter: writes a mixed RINEX 3.04 navigation file (RINEX 3.04 section 6,
// tables A6 GPS, A8 Galileo, A10 GLONASS, A12 QZSS, A14 BeiDou) from our record
// types, whatever decoded them (RTCM 3, UBX SFRBX). Numbers are written D19.12
// with an 'E' exponent. Epochs: GPS/QZSS/Galileo toc in GPST (GST reads as GPST),
// GLONASS tb in UTC, BeiDou toc in BDT, as RINEX prescribes.
#include <ostream>

#include "ppp_bayes_tree/types/beidou_ephemeris.h"
#include "ppp_bayes_tree/types/navigation_records.h"

namespace ppp {

class RinexNavWriter {
 public:
  explicit RinexNavWriter(std::ostream& out) : out_(out) {}
  void writeHeader(const std::string& program = "ppp_bayes_tree");
  void write(const GpsLnavEphemeris& eph);  // GPS or QZSS (by satellite system)
  void write(const GalileoEphemeris& eph);
  void write(const GlonassEphemeris& eph);
  void write(const BeidouEphemeris& eph);

 private:
  void epochLine(const SatelliteId& sat, const GnssTime& t, TimeSystem system, double a, double b, double c);
  void orbitLine(double a, double b, double c, double d, int count = 4);
  /// The epoch line (toc and clock terms) and broadcast orbits 1-4 shared by
  /// LNAV, Galileo and BeiDou records (issue of data, then the Kepler elements
  /// from Crs to OMEGA DOT; the reader's decodeKepler, fields 1-20).
  void keplerLines(const SatelliteId& sat, TimeSystem system, const ClockPolynomial& clock, double issue_of_data,
                   const KeplerOrbit& o);
  std::ostream& out_;
};

}  // namespace ppp
