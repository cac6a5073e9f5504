#pragma once
// Reader for Bias-SINEX 1.00 files ("SINEX_BIAS - Solution (Software/technique)
// INdependent EXchange Format for GNSS Biases, Version 1.00", S. Schaer, 2016):
// observable-specific (OSB), differential (DSB) and inter-system (ISB) biases
// of satellites and stations, e.g. CODE's *_OSB.BIA and WHU's *_ABS.BIA.
//
// Header line "%=BIA ..." and the BIAS/DESCRIPTION block are the header: when
// malformed they throw ParseError(file, line, reason). A malformed BIAS/SOLUTION
// row is skipped and reported (report.addProblem); reading goes on.
//
// Epochs "YYYY:DDD:SSSSS" are read in the TIME_SYSTEM of BIAS/DESCRIPTION (GPS
// when absent, counted in the report) and stored as GPST; "0000:000:00000" or a
// blank field means an open bound. Validity is inclusive at both ends; when
// several rows cover an instant, the one that started last wins. Start-only
// (time-stamp) rows are applied piecewise constant from their start; the
// format's optional linear interpolation between stamps is not implemented.
//
// Rows are checked (io/bias_bounds.h): a value beyond its bound (phase 100 ns,
// code 1000 ns) is a problem of its line and the row is not used. Rows of the same
// satellite (or station), type, observables and validity interval: repeats of the
// same value are counted and the first is kept; different values conflict, each
// later row is a problem naming the first row's line, and none of them is used.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/record_filter.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"
#include "ppp_bayes_tree/types/time_system.h"

namespace ppp {

enum class BiasType { OSB, DSB, ISB };
/// Unit of a row as written in the file.
enum class BiasUnit { Nanoseconds, Cycles };
/// Unit of a looked-up value: ns are converted to metres (x c x 1e-9), cycles
/// stay cycles (the wavelength, e.g. GLONASS FDMA, is the caller's business).
enum class BiasValueUnit { Metres, Cycles };

std::string_view biasTypeName(BiasType type);

/// One BIAS/SOLUTION row.
struct BiasRecord {
  BiasType type = BiasType::OSB;
  std::string svn;                       // "G080"; blank or a lone system letter for stations
  std::optional<SatelliteId> satellite;  // nullopt when the PRN field holds only a system
  GnssSystem system = GnssSystem::GPS;   // system of the PRN field
  std::string station;                   // blank for satellite biases
  ObservationCode obs1;
  std::optional<ObservationCode> obs2;   // DSB / ISB only
  std::optional<GnssTime> start;         // nullopt: open
  std::optional<GnssTime> end;           // nullopt: open
  BiasUnit unit = BiasUnit::Nanoseconds;
  double value = 0.0;                    // as written, in `unit`
  std::optional<double> std_dev;         // as written, in `unit`
  std::size_t line = 0;

  bool validAt(const GnssTime& t) const {
    return (!start || !(t < *start)) && (!end || !(*end < t));
  }
};

/// A looked-up bias in the unit given by `unit`.
struct BiasValue {
  double value = 0.0;
  BiasValueUnit unit = BiasValueUnit::Metres;
  std::optional<double> std_dev;  // same unit; nullopt when not given or derived
  /// True for a DSB computed as OSB(code1) - OSB(code2) (no DSB row in the file).
  bool derived_from_osb = false;
  std::size_t line = 0;  // the row used (the first one for a derived DSB)
};

/// Rows read but not used because they cannot be trusted.
struct BiasRowsRefused {
  std::size_t beyond_bound = 0;  // |value| above its bound
  std::size_t conflicting = 0;   // conflicting duplicates (every row of the conflict)
  std::size_t phase_rows = 0;    // of both, the phase (L) rows
  std::size_t first_phase_line = 0;  // the first refused phase row (0: none) and why
  std::string first_phase_reason;
  void countPhaseRow(std::size_t line, const std::string& reason) {
    ++phase_rows;
    if (first_phase_line == 0) {
      first_phase_line = line;
      first_phase_reason = reason;
    }
  }
};

/// "%=BIA" header line: version, agencies, creation time, data span, mode, count.
struct BiasSinexHeader {
  std::string version;      // "1.00"
  std::string file_agency;  // "COD"
  std::string data_agency;  // "IGS"
  std::optional<GnssTime> creation_time;
  std::optional<GnssTime> data_start;
  std::optional<GnssTime> data_end;
  char bias_mode = 'A';     // 'A' absolute, 'R' relative
  std::size_t estimate_count = 0;
};

/// BIAS/DESCRIPTION block (keywords of Bias-SINEX 1.00, section 4.3).
struct BiasDescription {
  std::optional<double> observation_sampling_s;
  std::optional<double> parameter_spacing_s;
  std::string determination_method;
  std::string bias_mode;  // "ABSOLUTE" or "RELATIVE"
  std::optional<TimeSystem> time_system;
  std::string apc_model;
  std::string receiver_clock_reference_gnss;
  /// SATELLITE_CLOCK_REFERENCE_OBSERVABLES per system, e.g. G -> {C1W, C2W}.
  std::map<GnssSystem, std::vector<std::string>> satellite_clock_reference_observables;
};

class BiasSinexFile {
 public:
  BiasSinexHeader header;
  BiasDescription description;
  /// FILE/REFERENCE: (INFO_TYPE, INFO) pairs in file order.
  std::vector<std::pair<std::string, std::string>> reference;
  std::vector<BiasRecord> records;
  ParseReport report;
  BiasRowsRefused refused;

  /// Satellite OSB of `code` valid at `t`; nullopt when absent.
  std::optional<BiasValue> osb(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const;
  /// Satellite DSB code1 - code2 at `t`: a DSB row (code1, code2), the negated
  /// row (code2, code1), or else OSB(code1) - OSB(code2) when both exist in the
  /// same unit (derived_from_osb = true). nullopt otherwise.
  std::optional<BiasValue> dsb(const SatelliteId& sat, const ObservationCode& code1,
                               const ObservationCode& code2, const GnssTime& t) const;
  /// Station OSB (rows with a station name) for a system.
  std::optional<BiasValue> stationOsb(std::string_view station, GnssSystem system,
                                      const ObservationCode& code, const GnssTime& t) const;
  /// Station names found (upper case as written).
  std::vector<std::string> stations() const;

  /// (Re)builds the lookup index; the reader calls it, call it again after
  /// editing `records`.
  void buildIndex();

 private:
  using Key = std::tuple<std::string, int, std::string, std::string>;  // owner, type, obs1, obs2
  const BiasRecord* find(const Key& key, const GnssTime& t) const;
  static std::string satelliteOwner(const SatelliteId& sat) { return sat.toString(); }
  static std::string stationOwner(std::string_view station, GnssSystem system);
  std::map<Key, std::vector<std::size_t>> index_;
};

/// Reads a Bias-SINEX file from a line source. Throws ParseError on a malformed
/// header line or BIAS/DESCRIPTION block. Only the rows of the filter's systems are
/// kept (its time window is not used: bias rows have validity intervals); the other
/// rows are counted, not parsed.
BiasSinexFile readBiasSinex(LineSource& source, const RecordFilter& filter = {});
/// Convenience: opens `path` (plain or gzip). Throws FileOpenError, ParseError.
BiasSinexFile readBiasSinexFile(const std::string& path, const RecordFilter& filter = {});

/// ppp_inspect view: version, span, satellites, observable codes per system,
/// counts per bias type, stations, report.
FileSummary summarizeBiasSinexFile(const std::string& path);

}  // namespace ppp
