#pragma once
// RinexObsHeader: the header of a RINEX observation file, versions 2.10/2.11,
// 3.02-3.05 and 4.00 (RINEX 2.11 sec. 5, table A1; RINEX 3.05 sec. 5, table A2;
// RINEX 4.00 table A2, whose observation header is that of 3.05 plus optional
// labels that we ignore).
//
// RINEX 2 "# / TYPES OF OBSERV" codes are mapped to RINEX 3 codes per system so
// that the rest of the project sees one kind of code; the original two-letter
// codes are kept in `rinex2_obs_types`. Mapping (ours; RINEX 2.11 does not say
// which tracking mode produced "L1" or "C2", we take the usual one):
//   GPS     C1->C1C P1->C1W L1->L1C D1->D1C S1->S1C
//           C2->C2X P2->C2W L2->L2W D2->D2W S2->S2W   band 5: C5->C5X (X = I+Q)
//   GLONASS C1->C1C P1->C1P L1->L1C D1->D1C S1->S1C
//           C2->C2C P2->C2P L2->L2P D2->D2P S2->S2P
//   Galileo, BeiDou, QZSS, IRNSS, SBAS, others: C<b>->C<b>X (all types), except
//           SBAS band 1: C1->C1C L1->L1C D1->D1C S1->S1C.
//   Any "P<b>" not listed above -> C<b>P.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/glonass_channels.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"
#include "ppp_bayes_tree/types/time_system.h"

namespace ppp {

/// One "SYS / PHASE SHIFT" record (RINEX 3.05 table A2): the quarter-cycle (or
/// other) shift applied to a phase observable, optionally for some satellites only.
struct PhaseShift {
  GnssSystem system = GnssSystem::GPS;
  ObservationCode code;
  std::optional<double> shift_cycles;      // blank: unknown (RINEX 3.01 files)
  std::vector<SatelliteId> satellites;     // empty: all satellites of the system
};

/// A time-of-first/last-obs header entry: the calendar reading as written and the
/// time system it is in, and the instant in GPST.
struct RinexHeaderTime {
  CalendarTime calendar;
  TimeSystem system = TimeSystem::GPS;
  GnssTime time;
};

struct RinexObsHeader {
  std::string version_text;  // as written, e.g. "3.04"
  double version = 0.0;      // 2.11, 3.04, 4.00
  int major_version = 0;     // 2, 3 or 4
  char file_system = 'G';    // column 41 of RINEX VERSION / TYPE: G R E C J S I M
  std::string program, run_by, date;

  std::string marker_name, marker_number, marker_type;
  std::string observer, agency;
  std::string receiver_number, receiver_type, receiver_version;
  std::string antenna_number;
  std::string antenna_type;    // model, columns 21-36 of ANT # / TYPE, trimmed
  std::string antenna_radome;  // columns 37-40 trimmed, as written (may be blank)
  /// ANTENNA: DELTA H/E/N [m] (height, east, north of the ARP above the marker).
  std::optional<Eigen::Vector3d> antenna_delta_hen_m;
  std::optional<Eigen::Vector3d> approx_position_ecef_m;

  /// Observation codes per system, in file order (index = column of the record).
  /// For RINEX 2 every system gets the mapped codes of the common list.
  std::array<std::vector<ObservationCode>, kNumGnssSystems> obs_types;
  /// RINEX 2 only: the original two-letter codes ("L1", "P2", ...).
  std::vector<std::string> rinex2_obs_types;
  /// RINEX 3 "SYS / SCALE FACTOR": the file values are the observation times this
  /// factor (1, 10, 100, 1000); the reader divides. 1 where not given.
  std::array<std::vector<double>, kNumGnssSystems> scale_factors;

  std::optional<double> interval_s;
  std::optional<RinexHeaderTime> time_of_first_obs;
  std::optional<RinexHeaderTime> time_of_last_obs;
  /// Time system of the epoch time tags (from TIME OF FIRST OBS, or the default
  /// of the file's system). RINEX "GLO" epochs are UTC (RINEX 3.05 sec. 6.2),
  /// so this is UTC for them.
  TimeSystem epoch_time_system = TimeSystem::GPS;
  std::optional<int> receiver_clock_offset_applied;
  std::optional<int> leap_seconds;
  std::string signal_strength_unit;

  GlonassChannels glonass_channels;
  int glonass_channel_entries = 0;  // number of GLONASS SLOT / FRQ # entries read
  std::vector<PhaseShift> phase_shifts;
  std::vector<std::string> comments;  // the first kMaxComments COMMENT lines
  std::size_t header_lines = 0;

  static constexpr std::size_t kMaxComments = 500;

  bool isRinex2() const { return major_version == 2; }
  /// Codes of one system (empty when the system has none).
  const std::vector<ObservationCode>& types(GnssSystem system) const {
    return obs_types[static_cast<int>(system)];
  }
  /// Antenna name as in ANTEX (model padded to 16 + radome, blank radome -> NONE),
  /// e.g. "TRM59800.00     NONE" (ANTEX 1.4 / IGS rcvr_ant.tab convention).
  std::string antexAntennaName() const;
  /// Radome, with a blank radome given as "NONE" (IGS convention).
  std::string radomeOrNone() const { return antenna_radome.empty() ? "NONE" : antenna_radome; }
};

/// Maps a RINEX 2 observation code ("C1", "P2", "L5") of a system to a RINEX 3
/// code (see the table above); nullopt when the code is not a RINEX 2 code.
std::optional<ObservationCode> mapRinex2ObsCode(GnssSystem system, std::string_view code);

/// Reads the header from the first line up to END OF HEADER. Throws ParseError
/// (file, line, reason) on a malformed header, a file that is not a RINEX
/// observation file, or an unsupported version.
RinexObsHeader readRinexObsHeader(LineSource& source);

/// Header-line parser, also used for the header lines of event-flag 4 records.
class RinexObsHeaderParser {
 public:
  explicit RinexObsHeaderParser(RinexObsHeader& header, std::string file)
      : header_(header), file_(std::move(file)) {}
  /// Handles one header line (not the first one). Returns true at END OF HEADER.
  bool line(std::string_view text, std::size_t line_number);
  /// Checks the pending continuation state; throws ParseError when a list is short.
  void finish(std::size_t line_number);
  /// Parses the RINEX VERSION / TYPE line.
  void versionLine(std::string_view text, std::size_t line_number);

 private:
  [[noreturn]] void fail(std::size_t line, const std::string& reason) const;
  /// The station and receiver labels (program, marker, observer, receiver, antenna,
  /// approximate position, comments); false for another label.
  bool stationLine(std::string_view label, std::string_view text, std::size_t line_number);
  /// The observation layout and time labels; false for another label.
  bool layoutLine(std::string_view label, std::string_view text, std::size_t line_number);
  void obsTypesRinex3(std::string_view text, std::size_t line_number);
  void obsTypesRinex2(std::string_view text, std::size_t line_number);
  void phaseShift(std::string_view text, std::size_t line_number);
  void glonassSlots(std::string_view text, std::size_t line_number);
  void scaleFactor(std::string_view text, std::size_t line_number);
  RinexHeaderTime headerTime(std::string_view text, std::size_t line_number);
  void checkPending(std::string_view label, std::size_t line_number);

  RinexObsHeader& header_;
  std::string file_;
  // Continuation state of multi-line records.
  int pending_types_ = 0;            // types still expected
  int pending_types_system_ = -1;    // system of a RINEX 3 list, -2 for RINEX 2
  std::size_t pending_types_line_ = 0;
  int pending_phase_sats_ = 0;       // satellites still expected for the last PHASE SHIFT
  int pending_glonass_ = 0;          // GLONASS slots still expected
  int pending_scale_ = 0;            // SCALE FACTOR codes still expected
  int pending_scale_system_ = -1;
  double pending_scale_factor_ = 1.0;
};

}  // namespace ppp
