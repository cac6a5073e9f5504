#include "ppp_bayes_tree/types/antenna_calibration.h"

#include <cstdio>
#include <cstdlib>

namespace ppp {

std::string FrequencyCalibration::code() const {
  char buf[8];
  std::snprintf(buf, sizeof(buf), "%c%02d", systemLetter(system), frequency % 100);
  return buf;
}

bool AntennaCalibration::validAt(const GnssTime& t) const {
  if (valid_from && t < *valid_from) return false;
  if (valid_until && t > *valid_until) return false;
  return true;
}

const FrequencyCalibration* AntennaCalibration::frequency(GnssSystem system, int number) const {
  for (const auto& f : frequencies) {
    if (f.system == system && f.frequency == number) return &f;
  }
  return nullptr;
}

FrequencyLookup AntennaCalibration::frequency(GnssSystem system, int number,
                                              FrequencyFallback fallback) const {
  FrequencyLookup out;
  out.calibration = frequency(system, number);
  if (out.calibration != nullptr) return out;
  FrequencyCalibration wanted;
  wanted.system = system;
  wanted.frequency = number;
  if (fallback == FrequencyFallback::NearestSameSystem) {
    for (const auto& f : frequencies) {
      if (f.system != system) continue;
      if (out.calibration == nullptr) {
        out.calibration = &f;
        continue;
      }
      const int d_new = std::abs(f.frequency - number);
      const int d_old = std::abs(out.calibration->frequency - number);
      if (d_new < d_old || (d_new == d_old && f.frequency < out.calibration->frequency)) {
        out.calibration = &f;
      }
    }
  }
  if (out.calibration != nullptr) {
    out.substituted = true;
    out.note = wanted.code() + " not calibrated for " + label() + ", using " + out.calibration->code();
  } else {
    out.note = wanted.code() + " not calibrated for " + label();
  }
  return out;
}

std::string AntennaCalibration::label() const {
  if (satellite) return model + " " + satellite->toString() + (svn.empty() ? "" : " (" + svn + ")");
  return model + " " + radome;
}

}  // namespace ppp
