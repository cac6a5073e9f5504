#include "ppp_bayes_tree/ppp/pipeline/product_set.h"

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/record_filter.h"

namespace ppp {

ProductSet ProductSet::load(const ProductFiles& files) {
  ProductSet set;
  if (!files.atx.empty()) {
    std::vector<AntexSource> antex;
    for (const auto& p : files.atx) {
      antex.push_back({fileBaseName(p), readAntexFile(p)});
      const AntexFile& file = antex.back().file;
      if (!file.report.clean()) set.problems_.push_back(file.report.headline(p));
      if (!file.skipped_satellite_codes.empty()) {
        std::string codes;
        for (const auto& c : file.skipped_satellite_codes) codes += " " + c;
        set.notes_.push_back("ANTEX " + antex.back().name + ": satellite blocks outside the systems' PRN ranges skipped:" +
                             codes);
      }
    }
    set.antennas_ = std::make_shared<const AntexCalibrations>(std::move(antex), files.satellite_family);
  }
  if (files.bias) {
    RecordFilter systems;
    systems.systems = files.systems;
    set.bias_file_ = std::make_unique<BiasSinexFile>(readBiasSinexFile(*files.bias, systems));
    if (!set.bias_file_->report.clean()) set.problems_.push_back(set.bias_file_->report.headline(*files.bias));
    set.bias_provider_ = std::make_unique<SinexBiasProvider>(*set.bias_file_, fileBaseName(*files.bias));
    set.notes_.push_back("code biases: " + fileBaseName(*files.bias) + " (OSB subtracted from the codes)");
  } else {
    set.notes_.push_back("code biases: no Bias-SINEX file; codes used as observed (product convention)");
  }
  if (files.blq) {
    set.blq_ = readBlqFile(*files.blq);
    if (!set.blq_->report.clean()) set.problems_.push_back(set.blq_->report.headline(*files.blq));
    set.blq_name_ = fileBaseName(*files.blq);
  }
  return set;
}

OceanLoadingLookup ProductSet::oceanLoading(const std::string& station) const {
  OceanLoadingLookup out;
  if (!blq_) return out;
  const BlqLookup found = blq_->find(station);
  out.coefficients = found.coefficients;
  if (out.coefficients) {
    out.note = "ocean loading: station " + out.coefficients->station + " from " + blq_name_ +
               (found.note.empty() ? "" : " (" + found.note + ")");
  } else {
    out.note = "ocean loading: station '" + station + "' not in " + blq_name_ + ", not applied" +
               (found.note.empty() ? "" : " (" + found.note + ")");
  }
  return out;
}

}  // namespace ppp
