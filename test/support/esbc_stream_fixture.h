#pragma once
// Test helper: the ESBC 2020-177 files of the shared data (esbc-2020-177/) and the
// SSR stream the tests make from them as ppp_ssr_encode does
// (models/ssr_from_precise.h): the GRG final SP3/CLK against the station's
// broadcast file, GPS, 5 s, centre of mass, each message one RTCM 3 frame.
#include <cstdint>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_encoder.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/ssr_from_precise.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "test_support.h"

namespace ppp::test {

/// Path of a file of the ESBC 2020-177 set, e.g. esbcPath("ESBC00DNK_R_20201770000_01D_MN.rnx").
inline std::string esbcPath(const std::string& file) { return dataPath("esbc-2020-177/" + file); }

/// The GRG final orbits (15 min SP3) and clocks (30 s CLK) of the day.
inline PreciseEphemeris esbcGrgPrecise() {
  return PreciseEphemeris::load({esbcPath("GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz")},
                                {esbcPath("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz")});
}

/// The day's PPP inputs with the GRG products: the 30 s observations, the GRG SP3/CLK,
/// the IGS20 GPS satellite antennas and the ESBC receiver antenna (shared data README).
inline PppInputFiles esbcGrgInputFiles() {
  PppInputFiles files;
  files.obs = esbcPath("ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz");
  files.sp3 = {esbcPath("GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz")};
  files.clk = {esbcPath("GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz")};
  files.atx = {dataPath("antex/igs20_gps_satellites_trim.atx"), dataPath("antex/igs05_esbc_receiver_trim.atx")};
  return files;
}

/// The options of the tests' SSR streams: GPS only; 5 s, centre of mass, combined
/// orbit+clock messages (the defaults).
inline SsrFromPreciseOptions esbcGpsSsrOptions() {
  SsrFromPreciseOptions options;
  options.systems = {GnssSystem::GPS};
  return options;
}

/// The messages of `ssr`, each encoded as one RTCM 3 frame, one after the other: the
/// bytes ppp_ssr_encode writes.
inline std::vector<std::uint8_t> ssrStreamBytes(const SsrFromPreciseResult& ssr) {
  std::vector<std::uint8_t> bytes;
  for (const auto& m : ssr.messages) {
    const auto frame = encodeSsrFrame(m);
    bytes.insert(bytes.end(), frame.begin(), frame.end());
  }
  return bytes;
}

/// The SSR stream for [first, last]: the GRG SP3/CLK against the broadcast records
/// `nav` (the station's file), esbcGpsSsrOptions().
inline std::vector<std::uint8_t> esbcGpsSsrStream(const NavData& nav, const GnssTime& first, const GnssTime& last) {
  return ssrStreamBytes(ssrFromPrecise({nav}, esbcGrgPrecise(), nullptr, nullptr, first, last, esbcGpsSsrOptions()));
}

}  // namespace ppp::test
