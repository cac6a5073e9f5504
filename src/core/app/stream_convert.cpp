#include "ppp_bayes_tree/app/stream_convert.h"

#include <fstream>
#include <set>
#include <stdexcept>
#include <tuple>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_writer.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_writer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"

namespace ppp {
namespace {

/// Every epoch of `source` into a RINEX 3 observation file; the number written.
std::size_t writeObservations(ObservationSource& source, const std::string& obs_path) {
  std::ofstream obs_out(obs_path);
  if (!obs_out) throw FileOpenError("cannot write " + obs_path);
  RinexObsWriter writer(obs_out);
  writer.writeHeader(source.header());
  std::size_t epochs = 0;
  ObsEpoch epoch;
  while (source.next(epoch) == ObservationRead::Epoch) {
    writer.writeEpoch(epoch, source.header());
    ++epochs;
  }
  return epochs;
}

/// A RINEX 3 navigation file opened and its header written.
struct RinexNavOutput {
  explicit RinexNavOutput(const std::string& path) : file(path), writer(file) {
    if (!file) throw FileOpenError("cannot write " + path);
    writer.writeHeader();
  }
  std::ofstream file;
  RinexNavWriter writer;
};

/// RXM-RAWX epochs and the GPS/Galileo/GLONASS/BeiDou records of RXM-SFRBX (io/ubx/ubx_observation_source.h).
StreamConversion convertUbxToRinex(const std::string& input, const std::string& obs_path,
                                   const std::optional<std::string>& nav_path) {
  StreamConversion result;
  result.format = StreamFormat::Ubx;
  UbxObservationSource source(input);
  result.epochs = writeObservations(source, obs_path);
  if (nav_path) {
    RinexNavOutput out(*nav_path);
    RinexNavWriter& nav = out.writer;
    for (const auto& e : source.navigation().gps) nav.write(e), ++result.navigation_records;
    for (const auto& e : source.navigation().galileo) nav.write(e), ++result.navigation_records;
    for (const auto& e : source.navigation().glonass) nav.write(e), ++result.navigation_records;
    for (const auto& e : source.navigation().beidou) nav.write(e), ++result.navigation_records;
  }
  result.counters = source.counters();
  return result;
}

}  // namespace

StreamConversion convertStreamToRinex(const std::string& input, const std::string& obs_path,
                                      const std::optional<std::string>& nav_path,
                                      const Rtcm3DecoderOptions& options) {
  StreamConversion result;
  result.format = detectStreamFormatOfFile(input);
  if (result.format == StreamFormat::Ubx) return convertUbxToRinex(input, obs_path, nav_path);
  if (result.format != StreamFormat::Rtcm3) {
    throw std::runtime_error(input + ": not an RTCM 3 or UBX stream (no frame with a good checksum found)");
  }
  RtcmObservationSource source(input, options);
  result.epochs = writeObservations(source, obs_path);
  if (nav_path) {
    RinexNavOutput out(*nav_path);
    RinexNavWriter& nav = out.writer;
    std::set<std::tuple<int, std::int64_t, int>> seen;
    const Rtcm3Output& n = source.scanNavigation();
    auto once = [&](int key, const GnssTime& t, int iod) {
      return seen.insert({key, t.wholeSeconds(), iod}).second;
    };
    for (const auto& e : n.gps)
      if (once(e.satellite.index(), e.orbit.toe, e.iode)) nav.write(e), ++result.navigation_records;
    for (const auto& e : n.galileo)
      if (once(e.satellite.index() + (e.type == GalileoNavType::FNav ? 10000 : 0), e.orbit.toe, e.iod_nav))
        nav.write(e), ++result.navigation_records;
    for (const auto& e : n.glonass)
      if (once(e.satellite.index(), e.tb, e.health)) nav.write(e), ++result.navigation_records;
    for (const auto& e : n.beidou)
      if (once(e.satellite.index(), e.orbit.toe, e.aode)) nav.write(e), ++result.navigation_records;
  }
  result.counters = source.scanCounters();
  return result;
}

}  // namespace ppp
