#pragma once
// SsrBiasProvider: the code and phase biases of an SSR stream as a
// BiasProvider. SSR biases are ADDED to the measurement (RTCM 10403.3 DF383,
// DF482: corrected = measured + bias); the BiasProvider convention is the
// Bias-SINEX OSB one (corrected = observed - bias), so the value answered is
// the negated SSR bias. An answer stays the answer from the message epoch to
// the next message of the satellite (at most the bias age limit).
#include <memory>
#include <string>

#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"

namespace ppp {

class SsrBiasProvider : public BiasProvider {
 public:
  SsrBiasProvider(std::shared_ptr<const SsrCorrectionStore> ssr, std::string stream_name)
      : ssr_(std::move(ssr)), name_(std::move(stream_name)) {}

  BiasAnswer codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  BiasAnswer phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  std::string describeSource() const override { return name_ + " (SSR code/phase biases)"; }

 private:
  std::shared_ptr<const SsrCorrectionStore> ssr_;
  std::string name_;
};

}  // namespace ppp
