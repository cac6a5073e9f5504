#include "ppp_bayes_tree/models/antex_calibrations.h"

#include "ppp_bayes_tree/io/rinex_obs_header.h"

namespace ppp {

ReceiverAntenna ReceiverAntenna::fromHeader(const RinexObsHeader& header) {
  ReceiverAntenna a;
  a.model = header.antenna_type;
  a.radome = header.antenna_radome;
  if (header.antenna_delta_hen_m) a.delta_hen_m = *header.antenna_delta_hen_m;
  return a;
}

ReceiverCalibrationLookup AntexCalibrations::receiver(const ReceiverAntenna& antenna) const {
  ReceiverCalibrationLookup out;
  const std::string asked = antenna.name();
  // An exact match in any file first (in file order), then a radome substitute.
  for (int pass = 0; pass < 2; ++pass) {
    for (const auto& src : files_) {
      const auto lookup = src.file.receiver(antenna.model, antenna.radome);
      if (lookup.antenna == nullptr || (pass == 0 && lookup.radome_substituted)) continue;
      out.calibration = lookup.antenna;
      out.source = "receiver " + asked + ": " + src.name;
      if (!lookup.note.empty()) out.source += " (" + lookup.note + ")";
      return out;
    }
  }
  out.source = "receiver " + asked + ": not found in any ANTEX file";
  return out;
}

SatelliteCalibrationLookup AntexCalibrations::satellite(const SatelliteId& sat, const GnssTime& t) const {
  for (const auto& src : files_) {
    if (const auto* a = src.file.satellite(sat, t)) return {a, src.name};
  }
  return {};
}

}  // namespace ppp
