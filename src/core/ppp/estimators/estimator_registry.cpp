#include "ppp_bayes_tree/ppp/estimators/estimator_registry.h"

#include "ppp_bayes_tree/ppp/estimators/epoch_estimator.h"

namespace ppp {

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
    for (const EstimatorEntry& e : kEstimators) all.push_back(&e);
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
