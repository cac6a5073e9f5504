#include "ppp_bayes_tree/ppp/product_set.h"

#include "ppp_bayes_tree/io/record_filter.h"

namespace ppp {
namespace {

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// One line for a file read with problems.
std::string readingProblem(const std::string& file, const ParseReport& report) {
  std::string text = file + ": " + std::to_string(report.problemCount()) + " problem(s) while reading";
  if (!report.problems().empty()) {
    const auto& first = report.problems().front();
    text += ", first: " + (first.line > 0 ? "line " + std::to_string(first.line) + ": " : std::string()) + first.reason;
  }
  return text;
}

}  // namespace

ProductSet ProductSet::load(const ProductFiles& files) {
  ProductSet set;
  if (!files.atx.empty()) {
    std::vector<AntexSource> antex;
    for (const auto& p : files.atx) {
      antex.push_back({baseName(p), readAntexFile(p)});
      if (!antex.back().file.report.clean()) set.problems_.push_back(readingProblem(p, antex.back().file.report));
    }
    set.antennas_ = std::make_shared<const AntexCalibrations>(std::move(antex));
  }
  if (files.bias) {
    RecordFilter systems;
    systems.systems = files.systems;
    set.bias_file_ = std::make_unique<BiasSinexFile>(readBiasSinexFile(*files.bias, systems));
    if (!set.bias_file_->report.clean()) set.problems_.push_back(readingProblem(*files.bias, set.bias_file_->report));
    set.bias_provider_ = std::make_unique<SinexBiasProvider>(*set.bias_file_, baseName(*files.bias));
    set.notes_.push_back("code biases: " + baseName(*files.bias) + " (OSB subtracted from the codes)");
  } else {
    set.notes_.push_back("code biases: no Bias-SINEX file; codes used as observed (product convention)");
  }
  if (files.blq) {
    set.blq_ = readBlqFile(*files.blq);
    if (!set.blq_->report.clean()) set.problems_.push_back(readingProblem(*files.blq, set.blq_->report));
    set.blq_name_ = baseName(*files.blq);
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
