#include "ppp_bayes_tree/models/antex_calibrations.h"

#include <cctype>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"

namespace ppp {
namespace {

/// The block of `sat` in one file: at `t`, or without a time the one that began last.
const AntennaCalibration* blockIn(const AntexFile& file, const SatelliteId& sat, const std::optional<GnssTime>& t) {
  if (t) return file.satellite(sat, *t);
  const AntennaCalibration* best = nullptr;
  for (const auto& a : file.antennas) {
    if (!a.satellite || *a.satellite != sat) continue;
    if (best == nullptr || (a.valid_from && (!best->valid_from || *best->valid_from < *a.valid_from))) best = &a;
  }
  return best;
}

}  // namespace

std::string antennaModelFamily(const std::string& model) {
  std::string out;
  for (char c : trim(model)) {
    if (c == '_' || c == '.') break;
    out.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  }
  return out;
}

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
  return satelliteBlock(sat, t);
}

SatelliteCalibrationLookup AntexCalibrations::satelliteBlock(const SatelliteId& sat,
                                                            const std::optional<GnssTime>& t) const {
  // The products' family first (in file order), then any family.
  for (int pass = satellite_family_.empty() ? 1 : 0; pass < 2; ++pass) {
    for (const auto& src : files_) {
      const auto* a = blockIn(src.file, sat, t);
      if (a != nullptr && (pass == 1 || antennaModelFamily(a->sinex_code) == satellite_family_)) return {a, src.name};
    }
  }
  return {};
}

}  // namespace ppp
