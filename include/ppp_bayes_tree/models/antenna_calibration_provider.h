#pragma once
// AntennaCalibrationProvider: where the measurement model gets antenna phase
// centre calibrations (PCO/PCV, antenna_calibration.h), and ReceiverAntenna,
// the description of the receiver's antenna it asks about. The model never sees
// the file (ANTEX today: AntexCalibrations; later e.g. a calibration stream or a
// user-supplied patch-antenna table).
#include <string>

#include <Eigen/Core>

#include "ppp_bayes_tree/types/antenna_calibration.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct RinexObsHeader;

/// The receiver's antenna: type, radome and the antenna reference point
/// offset from the marker (RINEX "ANTENNA: DELTA H/E/N", RTCM 1006/1033, ...).
struct ReceiverAntenna {
  std::string model;   // "TRM59800.00"
  std::string radome;  // "SCIS", blank = NONE
  /// ANTENNA: DELTA H/E/N [m] (up, east, north of the ARP above the marker).
  Eigen::Vector3d delta_hen_m = Eigen::Vector3d::Zero();

  /// "MODEL RADOME" with NONE for a blank radome.
  std::string name() const { return model + " " + (radome.empty() ? "NONE" : radome); }
  static ReceiverAntenna fromHeader(const RinexObsHeader& header);
};

/// A receiver calibration, or nullptr, and where it came from (or that it was not found).
struct ReceiverCalibrationLookup {
  const AntennaCalibration* calibration = nullptr;
  /// e.g. "receiver TRM59800.00 SCIS: igs20.atx (TRM59800.00 SCIS not found, using TRM59800.00 NONE)".
  std::string source;
};

/// A satellite calibration valid at an instant, or nullptr.
struct SatelliteCalibrationLookup {
  const AntennaCalibration* calibration = nullptr;
  std::string source;  // the file (or stream) it came from
};

class AntennaCalibrationProvider {
 public:
  virtual ~AntennaCalibrationProvider() = default;
  /// The calibration of a receiver antenna (pointer valid for the provider's lifetime).
  virtual ReceiverCalibrationLookup receiver(const ReceiverAntenna& antenna) const = 0;
  /// The calibration of a satellite's antenna valid at `t` (its validity period
  /// is in AntennaCalibration::valid_from / valid_until).
  virtual SatelliteCalibrationLookup satellite(const SatelliteId& sat, const GnssTime& t) const = 0;
};

}  // namespace ppp
