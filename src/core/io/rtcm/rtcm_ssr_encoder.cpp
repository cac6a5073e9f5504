#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"

#include <stdexcept>

#include "ppp_bayes_tree/io/bit_writer.h"
#include "ppp_bayes_tree/io/rtcm/rtcm3_framer.h"
#include "rtcm_ssr_layout.h"

namespace ppp {

std::vector<std::uint8_t> encodeSsrPayload(const SsrMessage& message) {
  SsrMessage m = message;  // the layout functions take non-const references
  const bool igs = m.header.igs_subtype != 0;
  const ssr_layout::TypeInfo info{m.header.system, m.header.kind};
  BitWriter w;
  if (igs) {
    const int subtype = ssr_layout::igsSubtype(info);
    if (subtype == 0) throw std::invalid_argument("no IGS-SSR message for this system and kind");
    w.putUnsigned(4076, 12);
    w.putUnsigned(static_cast<std::uint64_t>(m.header.igs_version), 3);
    w.putUnsigned(static_cast<std::uint64_t>(subtype), 8);
  } else {
    const int type = ssr_layout::rtcmType(info);
    if (type == 0) throw std::invalid_argument("no RTCM SSR message for this system and kind");
    w.putUnsigned(static_cast<std::uint64_t>(type), 12);
  }
  std::size_t nsat = 0;
  switch (m.header.kind) {
    case SsrMessageKind::Orbit:
    case SsrMessageKind::Combined: nsat = m.orbits.size(); break;
    case SsrMessageKind::Clock: nsat = m.clocks.size(); break;
    case SsrMessageKind::CodeBias: nsat = m.code_biases.size(); break;
    case SsrMessageKind::PhaseBias: nsat = m.phase_biases.size(); break;
    case SsrMessageKind::Ura: nsat = m.uras.size(); break;
    case SsrMessageKind::HighRateClock: nsat = m.high_rate_clocks.size(); break;
    case SsrMessageKind::Vtec:
      if (!m.vtec || m.vtec->layers.empty() || m.vtec->layers.size() > 4)
        throw std::invalid_argument("VTEC message: 1 to 4 layers needed");
      break;
  }
  if (nsat > 63) throw std::invalid_argument("an SSR message holds at most 63 satellites");
  ssr_layout::Writer io(w);
  std::vector<ssr_layout::BadSatellite> bad;
  ssr_layout::header(io, m, igs);
  if (m.header.kind == SsrMessageKind::Vtec) ssr_layout::vtecBlock(io, m);
  else ssr_layout::satelliteBlocks(io, m, igs, bad);
  return w.bytes();
}

std::vector<std::uint8_t> encodeSsrFrame(const SsrMessage& message) {
  return encodeRtcm3Frame(encodeSsrPayload(message));
}

}  // namespace ppp
