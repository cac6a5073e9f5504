#pragma once
// SsrBiasProvider: the code and phase biases of an SSR stream as a
// BiasProvider. SSR biases are ADDED to the measurement (RTCM 10403.3 DF383,
// DF482: corrected = measured + bias); the BiasProvider convention is the
// Bias-SINEX OSB one (corrected = observed - bias), so the value answered is
// the negated SSR bias. An answer stays the answer from the message epoch to
// the next message of the satellite (at most the bias age limit).
//
// A code is answered with the bias of its own signal. A GPS P(Y) code that the
// stream sends for another tracking mode of the same band (the Galileo HAS
// stream sends "L2 P", receivers track C2W) takes that one: P, Z-tracking (W)
// and Y are the one P(Y) signal at the satellite. Phase biases: own signal only.
//
// SSR biases belong to the SSR-corrected clocks. Where the orbit and clock
// corrections are missing or too old and broadcast orbits and clocks serve
// (the broadcast fallback of the live input and of ppp_solve --ssr,
// models/ssr_broadcast_fallback.h), the biases do not apply: `in_force` says
// so per satellite and instant, and the answer is then "no say"
// (BiasAnswer::applies false, no value): the codes are used as observed, as
// the broadcast clocks (and their TGD convention) expect. Such answers hold for
// the asked instant only.
#include <functional>
#include <memory>
#include <string>

#include "ppp_bayes_tree/models/bias_provider.h"
#include "ppp_bayes_tree/models/ssr_correction_store.h"

namespace ppp {

class SsrBiasProvider : public BiasProvider {
 public:
  /// True when the SSR corrections serve `sat` at `t` (precise orbits and clocks).
  using InForce = std::function<bool(const SatelliteId& sat, const GnssTime& t)>;

  /// `in_force` empty: the biases always apply (as loaded).
  SsrBiasProvider(std::shared_ptr<const SsrCorrectionStore> ssr, std::string stream_name, InForce in_force = {})
      : ssr_(std::move(ssr)), name_(std::move(stream_name)), in_force_(std::move(in_force)) {}

  BiasAnswer codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  BiasAnswer phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  std::string describeSource() const override { return name_ + " (SSR code/phase biases)"; }

 private:
  BiasAnswer bounded(BiasAnswer a, const GnssTime& t) const;

  std::shared_ptr<const SsrCorrectionStore> ssr_;
  std::string name_;
  InForce in_force_;
};

}  // namespace ppp
