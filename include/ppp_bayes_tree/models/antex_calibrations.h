#pragma once
// AntexCalibrations: the AntennaCalibrationProvider of one or more ANTEX files,
// searched in the given order: the first file holding an antenna wins. For a
// receiver, an exact type + radome match in any file comes first; only then a
// radome substitute (TYPE NONE, said in the source text).
//
// Satellites by family: when the products name the satellite antenna model they
// were made with (e.g. IGS14), a satellite's block is taken from the first file
// whose block for it is of that family (the SINEX code before its first '_':
// "IGS14_2178" -> IGS14), and only then from the first file holding one at all.
// So igs14.atx and igs20.atx given together in either order serve the products'
// family.
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/models/antenna_calibration_provider.h"

namespace ppp {

/// One ANTEX file and the name it is reported under (usually its file name).
struct AntexSource {
  std::string name;
  AntexFile file;
};

class AntexCalibrations : public AntennaCalibrationProvider {
 public:
  /// `satellite_family`: the family satellites are taken from first ("" = file order only).
  explicit AntexCalibrations(std::vector<AntexSource> files, std::string satellite_family = {})
      : files_(std::move(files)), satellite_family_(std::move(satellite_family)) {}

  ReceiverCalibrationLookup receiver(const ReceiverAntenna& antenna) const override;
  SatelliteCalibrationLookup satellite(const SatelliteId& sat, const GnssTime& t) const override;
  /// The block serving `sat` and its file (as satellite(sat, t)); without a time,
  /// the block that began last among those the family rule picks. Empty when none.
  SatelliteCalibrationLookup satelliteBlock(const SatelliteId& sat, const std::optional<GnssTime>& t) const;
  const std::vector<AntexSource>& files() const { return files_; }
  const std::string& satelliteFamily() const { return satellite_family_; }

 private:
  std::vector<AntexSource> files_;
  std::string satellite_family_;
};

/// The family of an antenna model name: the name up to its first '_' or '.',
/// upper case. "IGS14" for "IGS14_2108", "igs14_2108.atx" or "IGS14"; "" for "".
std::string antennaModelFamily(const std::string& model);

}  // namespace ppp
