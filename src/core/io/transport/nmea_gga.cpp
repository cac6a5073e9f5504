#include "ppp_bayes_tree/io/transport/nmea_gga.h"

#include <cmath>
#include <cstdio>

namespace ppp {

std::uint8_t nmeaChecksum(std::string_view sentence) {
  std::size_t begin = sentence.find('$');
  begin = begin == std::string_view::npos ? 0 : begin + 1;
  std::size_t end = sentence.find('*', begin);
  if (end == std::string_view::npos) end = sentence.size();
  std::uint8_t sum = 0;
  for (std::size_t i = begin; i < end; ++i) sum ^= static_cast<std::uint8_t>(sentence[i]);
  return sum;
}

std::string makeNmeaGga(double latitude_deg, double longitude_deg, double height_m,
                        double utc_seconds_of_day) {
  double t = std::fmod(utc_seconds_of_day, 86400.0);
  if (t < 0) t += 86400.0;
  const int hours = static_cast<int>(t / 3600.0);
  const int minutes = static_cast<int>((t - hours * 3600.0) / 60.0);
  const double seconds = t - hours * 3600.0 - minutes * 60.0;
  const double lat = std::fabs(latitude_deg), lon = std::fabs(longitude_deg);
  const int lat_deg = static_cast<int>(lat), lon_deg = static_cast<int>(lon);
  char body[160];
  std::snprintf(body, sizeof(body), "GPGGA,%02d%02d%05.2f,%02d%08.5f,%c,%03d%08.5f,%c,1,12,1.0,%.3f,M,0.000,M,,",
                hours, minutes, seconds, lat_deg, (lat - lat_deg) * 60.0, latitude_deg < 0 ? 'S' : 'N',
                lon_deg, (lon - lon_deg) * 60.0, longitude_deg < 0 ? 'W' : 'E', height_m);
  std::string sentence = std::string("$") + body;
  char tail[8];
  std::snprintf(tail, sizeof(tail), "*%02X\r\n", nmeaChecksum(sentence));
  return sentence + tail;
}

}  // namespace ppp
