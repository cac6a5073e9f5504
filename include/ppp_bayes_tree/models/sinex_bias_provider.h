#pragma once
// SinexBiasProvider: the BiasProvider of a Bias-SINEX file's satellite OSB rows
// (values in ns are converted to metres; rows in cycles are not served). A row
// holds from its start to its end, cut where a later row of the same satellite
// and signal starts (the row that started last wins, as BiasSinexFile::osb).
#include <string>

#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/models/bias_provider.h"

namespace ppp {

class SinexBiasProvider : public BiasProvider {
 public:
  /// `file` must outlive the provider; `name` is reported (usually the file name).
  SinexBiasProvider(const BiasSinexFile& file, std::string name) : file_(file), name_(std::move(name)) {}

  BiasAnswer codeBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  BiasAnswer phaseBias(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const override;
  std::string describeSource() const override { return name_ + " (Bias-SINEX OSB)"; }
  const BiasSinexFile& file() const { return file_; }

 private:
  BiasAnswer osb(const SatelliteId& sat, const ObservationCode& code, const GnssTime& t) const;
  const BiasSinexFile& file_;
  std::string name_;
};

}  // namespace ppp
