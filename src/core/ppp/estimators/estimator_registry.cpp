#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"

#include "ppp_bayes_tree/ppp/estimators/estimator_options.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ekf.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ins_ekf.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_ins_smoother.h"
#include "ppp_bayes_tree/ppp/estimators/ppp_smoother.h"

namespace ppp {

std::unique_ptr<PppEstimator> makePppEkf(const EstimatorOptions& options) {
  return std::make_unique<PppEkf>(options);
}

std::unique_ptr<PppEstimator> makePppSmoother(const EstimatorOptions& options) {
  return std::make_unique<PppSmoother>(options);
}

std::unique_ptr<PppEstimator> makePppInsEkf(const EstimatorOptions& options) {
  return std::make_unique<PppInsEkf>(options);
}

std::unique_ptr<PppEstimator> makePppInsSmoother(const EstimatorOptions& options) {
  return std::make_unique<PppInsSmoother>(options);
}

namespace {

/// The names "both" runs, joined by `separator`.
std::string allEstimatorNames(std::string_view separator) {
  std::string out;
  for (const EstimatorEntry& e : kEstimators) {
    if (!runsInAll(e)) continue;
    if (!out.empty()) out += separator;
    out += e.name;
  }
  return out;
}

}  // namespace

std::unique_ptr<PppEstimator> makeEstimator(std::string_view name, const EstimatorOptions& options, std::string* why) {
  if (const EstimatorEntry* e = findEstimator(name)) return e->make(options);
  if (why) {
    const std::string value(name);
    *why = name == kAllEstimators ? "estimator '" + value + "' is run by the caller as " +
                                        allEstimatorNames(" and ") + " (one pipeline each)"
                                  : "unknown estimator '" + value + "' (expected " +
                                        registeredEstimatorNames(" or ") + ")";
  }
  return nullptr;
}

const EstimatorEntry* findEstimator(std::string_view name) {
  for (const EstimatorEntry& e : kEstimators)
    if (e.name == name) return &e;
  return nullptr;
}

std::string registeredEstimatorNames(std::string_view separator) {
  std::string out;
  for (const EstimatorEntry& e : kEstimators) {
    if (!out.empty()) out += separator;
    out += e.name;
  }
  return out;
}

std::set<std::string> estimatorChoices() {
  std::set<std::string> out;
  for (const EstimatorEntry& e : kEstimators) out.emplace(e.name);
  out.emplace(kAllEstimators);
  return out;
}

std::optional<std::vector<const EstimatorEntry*>> selectEstimators(std::string_view value, std::string* why) {
  if (value == kAllEstimators) {
    std::vector<const EstimatorEntry*> all;
    for (const EstimatorEntry& e : kEstimators)
      if (runsInAll(e)) all.push_back(&e);
    return all;
  }
  if (const EstimatorEntry* e = findEstimator(value)) return std::vector<const EstimatorEntry*>{e};
  if (why) {
    *why = "unknown estimator '" + std::string(value) + "' (expected " + registeredEstimatorNames(", ") + " or " +
           std::string(kAllEstimators) + ")";
  }
  return std::nullopt;
}

std::vector<EstimatorSolution> solutionOutputs(const EstimatorEntry& entry) {
  const std::string name(entry.name), label(entry.label);
  if (!entry.smoothed()) return {{name, name, label, false}};
  return {{name + "_filtered", name + " filtered", label + " filtered", false},
          {name + "_smoothed", name + " smoothed", label + " smoothed", true}};
}

}  // namespace ppp
