#pragma once
// AntennaCalibration: one ANTEX 1.4 antenna block (a receiver antenna type or a
// satellite antenna over a validity period): per-frequency phase-centre offset
// (PCO) and phase-centre variations (PCV). Values are stored in metres; angles
// of the grid stay in degrees as written (see pcv_grid.h).
//
// Frames (ANTEX 1.4, section "NORTH / EAST / UP"):
//  - receiver antenna: PCO is north, east, up from the antenna reference point;
//  - satellite antenna: PCO is x, y, z in the IGS satellite body frame, from the
//    centre of mass.
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/types/pcv_grid.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

/// Calibration of one frequency ("START OF FREQUENCY" .. "END OF FREQUENCY").
struct FrequencyCalibration {
  GnssSystem system = GnssSystem::GPS;
  int frequency = 1;  // ANTEX frequency number: G01, G02, G05, R01, E05, C07, ...
  /// Receiver: (north, east, up) [m]; satellite: (x, y, z) body frame [m].
  Eigen::Vector3d pco_m = Eigen::Vector3d::Zero();
  PcvGrid pcv;

  std::string code() const;  // "G01"
  /// PCV [m] at a zenith/nadir angle and azimuth [rad]; nullopt outside the
  /// grid (refused, never clamped: see pcv_grid.h).
  std::optional<double> pcv_m(double zenith_rad, double azimuth_rad) const {
    return pcv.evaluate_m(zenith_rad, azimuth_rad);
  }
};

/// Which frequency to use when the requested one is not calibrated.
enum class FrequencyFallback {
  None,                // explicit absence
  NearestSameSystem,   // the calibrated frequency of the same system with the
                       // closest number (ties: the lower), reported in the note
};

/// Result of a frequency lookup with optional fallback.
struct FrequencyLookup {
  const FrequencyCalibration* calibration = nullptr;  // nullptr: absent
  bool substituted = false;
  std::string note;  // e.g. "G05 not calibrated for BLOCK IIR-M G05, using G02"
};

struct AntennaCalibration {
  std::string type;    // the 20-character field trimmed, e.g. "TRM59800.00     NONE"
  std::string model;   // columns 1-16 trimmed, e.g. "TRM59800.00" or "BLOCK IIR-M"
  std::string radome;  // columns 17-20 trimmed (receivers; "NONE" when blank)
  std::string serial;  // receivers: serial number or blank (type mean)
  std::optional<SatelliteId> satellite;  // satellites: PRN code from the serial field
  std::string svn;     // satellites: SVN code, e.g. "G050"
  std::string cospar_id;  // satellites: e.g. "2009-043A"
  std::string sinex_code;
  std::optional<GnssTime> valid_from;   // GPST; nullopt: no lower bound
  std::optional<GnssTime> valid_until;  // GPST; nullopt: no upper bound
  double azimuth_step_deg = 0.0;  // DAZI
  double zenith_first_deg = 0.0;  // ZEN1
  double zenith_last_deg = 0.0;   // ZEN2
  double zenith_step_deg = 0.0;   // DZEN
  std::vector<FrequencyCalibration> frequencies;
  std::size_t rms_blocks_skipped = 0;
  std::size_t line = 0;  // line of "START OF ANTENNA" in the file

  bool isSatellite() const { return satellite.has_value(); }
  /// True when `t` lies in [valid_from, valid_until] (open bounds when absent).
  bool validAt(const GnssTime& t) const;
  /// The calibration of one frequency; nullptr when not in the block.
  const FrequencyCalibration* frequency(GnssSystem system, int number) const;
  /// Same, with an optional fallback to another frequency of the same system.
  FrequencyLookup frequency(GnssSystem system, int number, FrequencyFallback fallback) const;
  /// "TRM59800.00 NONE" for receivers, "BLOCK IIR-M G05 (G050)" for satellites.
  std::string label() const;
};

}  // namespace ppp
