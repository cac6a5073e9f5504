#pragma once
// What ppp_stream_inspect (and ppp_inspect, for a stream file) tells about a
// receiver or correction recording: frames per message type, epochs, span, rate
// and gaps, checksum errors and other problems (with byte offsets), satellites
// and signals per system, ephemerides, the station. One decode of the file.
//
// RTCM SSR messages go to the SSR decoder (io/rtcm/rtcm_ssr_decoder.h): providers,
// solutions, update intervals, datum and counts in the `ssr` block. A u-blox
// file is read through io/ubx/ubx_observation_source.h.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"

namespace ppp {

struct StreamGap {
  GnssTime after;  // last epoch before the gap
  double length_s = 0.0;
};

struct StreamInspection {
  std::string path;
  StreamFormat format = StreamFormat::Unknown;
  StreamCounters counters;
  std::map<int, std::uint64_t> decoded_by_type, ignored_by_type;
  std::size_t epochs = 0;
  std::optional<GnssTime> first_epoch, last_epoch;
  std::optional<double> interval_s;  // the most common epoch spacing
  std::size_t gap_count = 0;         // spacings above 1.5 intervals
  std::vector<StreamGap> gaps;       // the first 20
  std::size_t backwards = 0;         // epochs not after the previous one
  std::map<GnssSystem, std::set<SatelliteId>> satellites;
  std::map<GnssSystem, std::set<std::string>> signals;  // "1C", "2W"
  std::map<GnssSystem, std::size_t> ephemeris_records;  // decoded records (repeats included)
  std::map<GnssSystem, std::set<SatelliteId>> ephemeris_satellites;
  RtcmStationInfo station;
  GlonassChannels glonass_channels;
  std::uint64_t beidou_gpst_messages = 0;
  /// SSR section (providers, solutions, update intervals, datum, counts): the
  /// SSR decoder's summary lines; empty when the stream holds no SSR.
  std::vector<std::string> ssr;
};

/// Decodes the whole file, RTCM 3 or UBX (throws FileOpenError; std::runtime_error for another format).
StreamInspection inspectStreamFile(const std::string& path, const Rtcm3DecoderOptions& options = {});
std::string formatStreamInspection(const StreamInspection& inspection);
std::string streamInspectionJson(const StreamInspection& inspection);
/// The ppp_inspect summary of a stream file.
FileSummary summarizeStreamFile(const std::string& path);

}  // namespace ppp
