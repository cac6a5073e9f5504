#include "ppp_bayes_tree/io/transport/stream_format.h"

#include <cstdio>
#include <memory>
#include <vector>

#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

std::string_view streamFormatName(StreamFormat format) {
  switch (format) {
    case StreamFormat::Rtcm3: return "RTCM 3 stream";
    case StreamFormat::Ubx: return "u-blox UBX stream";
    case StreamFormat::Unknown: return "unknown";
  }
  return "unknown";
}

StreamFormat detectStreamFormat(const std::uint8_t* d, std::size_t n) {
  for (std::size_t i = 0; i + 6 <= n; ++i) {
    if (d[i] == 0xD3 && (d[i + 1] & 0xFC) == 0) {
      const std::size_t len = ((d[i + 1] & 0x03u) << 8) | d[i + 2];
      if (len >= 2 && i + 3 + len + 3 <= n) {
        const std::uint32_t crc = crc24q(d + i, 3 + len);
        const std::uint32_t got = (std::uint32_t(d[i + 3 + len]) << 16) | (std::uint32_t(d[i + 4 + len]) << 8) |
                                  d[i + 5 + len];
        if (crc == got) return StreamFormat::Rtcm3;
      }
    }
    if (d[i] == 0xB5 && d[i + 1] == 0x62) {
      const std::size_t len = d[i + 4] | (std::size_t(d[i + 5]) << 8);
      if (i + 6 + len + 2 <= n) {
        std::uint8_t a = 0, b = 0;
        for (std::size_t k = i + 2; k < i + 6 + len; ++k) {
          a = static_cast<std::uint8_t>(a + d[k]);
          b = static_cast<std::uint8_t>(b + a);
        }
        if (a == d[i + 6 + len] && b == d[i + 7 + len]) return StreamFormat::Ubx;
      }
    }
  }
  return StreamFormat::Unknown;
}

StreamFormat detectStreamFormatOfFile(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw FileOpenError("cannot open " + path);
  std::vector<std::uint8_t> buf(1 << 16);
  const std::size_t n = std::fread(buf.data(), 1, buf.size(), f.get());
  return detectStreamFormat(buf.data(), n);
}

std::optional<GnssTime> parseReferenceDate(std::string_view text) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double s = 0.0;
  const std::string t(text);
  const int n = std::sscanf(t.c_str(), "%d/%d/%d %d:%d:%lf", &y, &mo, &d, &h, &mi, &s);
  if (n != 3 && n != 6) return std::nullopt;
  if (!isValidDate(y, mo, d) || h < 0 || h > 23 || mi < 0 || mi > 59 || s < 0.0 || s >= 60.0) return std::nullopt;
  CalendarTime c{y, mo, d, h, mi, s};
  return GnssTime::fromCalendar(c, TimeSystem::GPS);
}

}  // namespace ppp
