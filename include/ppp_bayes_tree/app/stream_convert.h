#pragma once
// The conversion behind ppp_stream_convert: a receiver recording (RTCM 3; UBX
// once its source is wired in) to RINEX 3.04 observation and navigation files,
// as RTKLIB convbin does. Navigation records are written once each (the stream
// repeats them), in stream order.
#include <optional>
#include <string>

#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/transport/stream_format.h"

namespace ppp {

struct StreamConversion {
  StreamFormat format = StreamFormat::Unknown;
  std::size_t epochs = 0;
  std::size_t navigation_records = 0;
  StreamCounters counters;  // of the whole file
};

/// Throws FileOpenError on unreadable input or unwritable output, std::runtime_error
/// for a format that is not (yet) supported.
StreamConversion convertStreamToRinex(const std::string& input, const std::string& obs_path,
                                      const std::optional<std::string>& nav_path,
                                      const Rtcm3DecoderOptions& options);

}  // namespace ppp
