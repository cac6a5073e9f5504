#pragma once
// Fuzz entry for the RTCM 3 decoder: bytes -> Rtcm3Decoder (fed in two chunks,
// with a reference date so that the MSM paths run), the decoded epochs through
// the RINEX conversion (StreamSignalInventory, streamEpochToObsEpoch,
// RinexObsWriter) and back through the MSM7 encoder and the decoder. The decoder
// throws nothing on any input; nothing is caught here.
#include <cstddef>
#include <cstdint>
#include <sstream>

#include "ppp_bayes_tree/io/rinex/rinex_nav_writer.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_writer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_decoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_msm_encoder.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"

namespace ppp::fuzz {

inline void fuzzRtcm(const std::uint8_t* data, std::size_t size) {
  Rtcm3DecoderOptions options;
  options.reference_time = GnssTime::fromGpsWeek(2200, 302400.0);
  Rtcm3Decoder decoder(options);
  const std::size_t half = size / 2;
  decoder.feed(data, half);
  decoder.feed(data + half, size - half);
  decoder.finish();
  Rtcm3Output& out = decoder.output();
  (void)decoder.counters().totalProblems();

  StreamSignalInventory inventory;
  for (const auto& e : out.epochs) inventory.add(e);
  RinexObsHeader header;
  inventory.fillTypes(header);
  fillStationHeader(decoder.station(), header);
  std::ostringstream os;
  RinexObsWriter writer(os);
  writer.writeHeader(header);
  ObsEpoch epoch;
  MsmEncodeOptions enc;
  enc.glonass_channels = decoder.glonassChannels();
  Rtcm3Decoder again(options);
  for (const auto& e : out.epochs) {
    streamEpochToObsEpoch(e, header, epoch);
    writer.writeEpoch(epoch, header);
    for (GnssSystem s : {GnssSystem::GPS, GnssSystem::GLONASS, GnssSystem::Galileo, GnssSystem::SBAS,
                         GnssSystem::QZSS, GnssSystem::BeiDou}) {
      for (const auto& payload : encodeMsm7(e, s, enc)) {
        if (payload.size() > 1023) continue;
        const auto frame = encodeRtcm3Frame(payload);
        again.feed(frame.data(), frame.size());
      }
    }
  }
  again.finish();
  RinexNavWriter nav(os);
  for (const auto& r : out.gps) nav.write(r);
  for (const auto& r : out.galileo) nav.write(r);
  for (const auto& r : out.glonass) nav.write(r);
  for (const auto& r : out.beidou) nav.write(r);
}

}  // namespace ppp::fuzz
