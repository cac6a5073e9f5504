#pragma once
// ProductSet: the correction products besides orbits and clocks that a PPP run
// loads from files: antenna calibrations (ANTEX, searched in the given order),
// satellite code biases (Bias-SINEX OSB) and ocean-loading coefficients (BLQ).
// ppp_solve (PppPipeline) and the ROS nodes load them the same way, and both
// hand the same providers to the epoch processor. notes() says what was loaded.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/products/blq_reader.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"
#include "ppp_bayes_tree/models/sinex_bias_provider.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct ProductFiles {
  std::vector<std::string> atx;
  std::optional<std::string> bias, blq;
  /// Systems processed: the bias file is read for these only.
  std::vector<GnssSystem> systems{GnssSystem::GPS};
  /// The satellite antenna family taken first (AntexCalibrations; "" = file order).
  std::string satellite_family;
};

/// Ocean loading of a station: the coefficients (nullptr: none) and a note.
struct OceanLoadingLookup {
  const OceanLoadingCoefficients* coefficients = nullptr;
  std::string note;  // empty when no BLQ file was given
};

class ProductSet {
 public:
  /// Reads the files (throws FileOpenError / ParseError).
  static ProductSet load(const ProductFiles& files);
  ProductSet() = default;
  ProductSet(ProductSet&&) = default;
  ProductSet& operator=(ProductSet&&) = default;

  /// The ANTEX files' calibrations (null when no ANTEX file was given).
  std::shared_ptr<const AntexCalibrations> antennas() const { return antennas_; }
  std::size_t antexFiles() const { return antennas_ ? antennas_->files().size() : 0; }
  /// The code biases (nullptr: no bias file; valid while the set lives).
  const BiasProvider* biases() const { return bias_provider_.get(); }
  const BiasSinexFile* biasFile() const { return bias_file_.get(); }
  /// The station's ocean loading (by marker name) from the BLQ file.
  OceanLoadingLookup oceanLoading(const std::string& station) const;
  /// "code biases: ...", "ANTEX ...: ... skipped", in load order.
  const std::vector<std::string>& notes() const { return notes_; }
  /// What went wrong while reading the files (truncation, skipped blocks and
  /// records, cut lines), one line per file: "<file>: N problem(s) while reading,
  /// first: line L: reason". Whatever such a file lost is missing from the run.
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::shared_ptr<const AntexCalibrations> antennas_;
  std::unique_ptr<BiasSinexFile> bias_file_;  // stable address for the provider
  std::unique_ptr<SinexBiasProvider> bias_provider_;
  std::optional<BlqFile> blq_;
  std::string blq_name_;
  std::vector<std::string> notes_;
  std::vector<std::string> problems_;
};

}  // namespace ppp
