#pragma once
// SSR corrections: the State Space Representation values of RTCM 10403.3
// (section 3.5.12: messages 1057-1068 GPS/GLONASS, 1240-1263 Galileo/QZSS/SBAS/
// BeiDou, 1264 VTEC, 1265-1270 phase biases) and of the IGS-SSR format v1.00
// (message 4076), in SI units with the units in the names.
//
// Conventions (RTCM 10403.3, 3.5.12.x):
//  - orbit: radial/along/cross correction dO(t) = dO + dO_dot (t - t0); the
//    corrected position is X = X_brdc - (e_r dr + e_a da + e_c dc) with
//    e_a = v/|v|, e_c = r x v / |r x v|, e_r = e_a x e_c (broadcast r, v);
//  - clock: dC(t) = C0 + C1 (t - t0) + C2 (t - t0)^2 [m] (+ high-rate clock);
//    the corrected satellite clock is dt = dt_brdc + dC / c;
//  - code / phase bias: ADDED to the measurement (corrected = measured + bias),
//    i.e. the opposite sign of a Bias-SINEX OSB.
// t0 is the SSR epoch time. Each value keeps the issue of data (IOD) of the
// broadcast record it refers to.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// What an SSR message carries.
enum class SsrMessageKind { Orbit, Clock, Combined, CodeBias, PhaseBias, Ura, HighRateClock, Vtec };
std::string_view ssrMessageKindName(SsrMessageKind kind);

/// SSR update interval (DF391 / IDF004) code -> seconds (RTCM 10403.3 table 3.5-74):
/// 1, 2, 5, 10, 15, 30, 60, 120, 240, 300, 600, 900, 1800, 3600, 7200, 10800 s.
double ssrUpdateInterval_s(int code);
/// The code for an interval (nullopt when it is not one of the table's values).
std::optional<int> ssrUpdateIntervalCode(double interval_s);

/// The header fields common to every SSR message.
struct SsrHeader {
  int message_type = 0;       // DF002 (4076 for IGS-SSR)
  int igs_subtype = 0;        // IGS-SSR message number IDF002 (0: an RTCM message)
  int igs_version = 0;        // IGS-SSR version IDF001
  GnssSystem system = GnssSystem::GPS;
  SsrMessageKind kind = SsrMessageKind::Orbit;
  /// Epoch time as sent: seconds of the GPS / Galileo / BeiDou week, or of the
  /// GLONASS day (RTCM GLONASS messages), whole seconds (DF385 / DF386 / IDF003).
  std::uint32_t epoch_time_s = 0;
  /// The epoch in GPST, when a week (or day) could be taken from the context.
  std::optional<GnssTime> epoch;
  int update_interval_code = 0;
  double update_interval_s = 1.0;
  bool multiple_message = false;       // DF388: more messages of this epoch follow
  std::optional<bool> datum_regional;  // DF375 (orbit messages only): false = ITRF
  int iod_ssr = 0;                     // DF413
  int provider_id = 0;                 // DF414
  int solution_id = 0;                 // DF415
  // Where the message came from in the stream.
  std::uint64_t byte_offset = 0;
  std::uint64_t frame_index = 0;
};

struct SsrOrbitCorrection {
  SatelliteId satellite;
  int iod = 0;  // GPS/QZSS IODE, Galileo IODnav, GLONASS tb index (DF392); RTCM BeiDou: toe modulo (10 bits), IGS-SSR BeiDou: IOD
  std::optional<std::uint32_t> iod_aux;  // RTCM only: BeiDou IOD (8 bits), SBAS IODCRC (24 bits)
  double radial_m = 0.0, along_m = 0.0, cross_m = 0.0;
  double radial_dot_mps = 0.0, along_dot_mps = 0.0, cross_dot_mps = 0.0;
};

struct SsrClockCorrection {
  SatelliteId satellite;
  double c0_m = 0.0, c1_m_per_s = 0.0, c2_m_per_s2 = 0.0;
};

struct SsrHighRateClock {
  SatelliteId satellite;
  double clock_m = 0.0;  // added to C0 (DF404)
};

struct SsrUra {
  SatelliteId satellite;
  int ura_class = 0, ura_value = 0;  // DF389: 3 + 3 bits
  /// URA [m] = 3^class (1 + value/4) - 1 mm; nullopt for the "undefined" code 0
  /// and for the "> 5466.5 mm" code 63.
  std::optional<double> ura_m;
};

/// One signal's code bias. `code` is the RINEX code of the signal id (nullopt
/// when the id is reserved in the system's table).
struct SsrSignalCodeBias {
  int signal_id = 0;
  std::optional<ObservationCode> code;
  double bias_m = 0.0;
};
struct SsrCodeBias {
  SatelliteId satellite;
  std::vector<SsrSignalCodeBias> biases;
};

struct SsrSignalPhaseBias {
  int signal_id = 0;
  std::optional<ObservationCode> code;
  bool integer = false;            // DF483 signal integer indicator
  int widelane_integer = 0;        // DF484: 0 none, 1 WL integer with 1 others, 2 with all, 3 reserved
  int discontinuity_counter = 0;   // DF485
  double bias_m = 0.0;             // DF482
};
struct SsrPhaseBias {
  SatelliteId satellite;
  double yaw_rad = 0.0;            // DF480
  double yaw_rate_rad_per_s = 0.0; // DF481
  std::vector<SsrSignalPhaseBias> biases;
};

/// VTEC spherical harmonics (1264 / IGS-SSR 201): one per layer.
struct SsrVtecLayer {
  double height_m = 0.0;
  int degree = 0, order = 0;
  std::vector<double> cosine_tecu, sine_tecu;  // as sent, in the standard's order
};
struct SsrVtec {
  double quality_tecu = 0.0;  // DF478
  std::vector<SsrVtecLayer> layers;
};

/// One decoded SSR message: the header and the per-satellite values of its kind
/// (a combined message fills both orbits and clocks).
struct SsrMessage {
  SsrHeader header;
  std::vector<SsrOrbitCorrection> orbits;
  std::vector<SsrClockCorrection> clocks;
  std::vector<SsrHighRateClock> high_rate_clocks;
  std::vector<SsrUra> uras;
  std::vector<SsrCodeBias> code_biases;
  std::vector<SsrPhaseBias> phase_biases;
  std::optional<SsrVtec> vtec;
  // Phase-bias messages only: DF486 dispersive bias consistency, DF487 MW consistency.
  bool dispersive_consistent = false, mw_consistent = false;
};

/// RTCM SSR signal id -> RINEX code (RTCM 10403.3 tables 3.5-91 GPS, 3.5-93
/// GLONASS, 3.5-96 Galileo, 3.5-99 QZSS, 3.5-102 SBAS, 3.5-105 BeiDou);
/// IGS-SSR v1.00 uses its own tables (section 7): `igs_ssr` selects them.
std::optional<ObservationCode> ssrSignalCode(GnssSystem system, int signal_id, bool igs_ssr);
/// The inverse (nullopt when the signal has no id in the table).
std::optional<int> ssrSignalId(GnssSystem system, const ObservationCode& code, bool igs_ssr);

}  // namespace ppp
