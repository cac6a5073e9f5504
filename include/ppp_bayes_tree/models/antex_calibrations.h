#pragma once
// AntexCalibrations: the AntennaCalibrationProvider of one or more ANTEX files,
// searched in the given order: the first file holding an antenna wins. For a
// receiver, an exact type + radome match in any file comes first; only then a
// radome substitute (TYPE NONE, said in the source text).
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/antex_reader.h"
#include "ppp_bayes_tree/models/antenna_calibration_provider.h"

namespace ppp {

/// One ANTEX file and the name it is reported under (usually its file name).
struct AntexSource {
  std::string name;
  AntexFile file;
};

class AntexCalibrations : public AntennaCalibrationProvider {
 public:
  explicit AntexCalibrations(std::vector<AntexSource> files) : files_(std::move(files)) {}

  ReceiverCalibrationLookup receiver(const ReceiverAntenna& antenna) const override;
  SatelliteCalibrationLookup satellite(const SatelliteId& sat, const GnssTime& t) const override;
  const std::vector<AntexSource>& files() const { return files_; }

 private:
  std::vector<AntexSource> files_;
};

}  // namespace ppp
