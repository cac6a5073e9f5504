#include "ppp_bayes_tree/ppp/ambiguity/antenna_model_consistency.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/models/antex_calibrations.h"

namespace ppp {
namespace {

void addDistinct(std::vector<std::string>& v, const std::string& s) {
  if (!s.empty() && std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
}

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : " + ") + s;
  return out.empty() ? std::string("not stated") : out;
}

}  // namespace

std::vector<std::string> satelliteAntennaModels(const AntexCalibrations& antex) {
  std::vector<std::string> out;
  for (const auto& f : antex.files())
    for (const auto& a : f.file.antennas)
      if (a.isSatellite()) addDistinct(out, std::string(trim(a.sinex_code)));
  return out;
}

std::vector<std::string> usedSatelliteAntennaModels(const AntexCalibrations& antex,
                                                    const std::vector<SatelliteId>& satellites,
                                                    const std::optional<GnssTime>& t) {
  std::vector<std::string> out;
  for (const auto& sat : satellites)
    if (const auto* a = antex.satelliteBlock(sat, t).calibration) addDistinct(out, std::string(trim(a->sinex_code)));
  return out;
}

AntennaModelCheck checkAntennaModelConsistency(const std::vector<std::string>& product_models,
                                               const std::vector<std::string>& antex_models) {
  AntennaModelCheck out;
  std::set<std::string> product_families, antex_families;
  for (const auto& named : product_models) {
    std::string m(trim(named));  // "igs14_2108" (clock file name) and "IGS14_2108" (SP3) are one model
    for (auto& c : m) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    addDistinct(out.product_models, m);
    if (!antennaModelFamily(m).empty()) product_families.insert(antennaModelFamily(m));
  }
  for (const auto& m : antex_models) {
    addDistinct(out.antex_models, m);
    if (!antennaModelFamily(m).empty()) antex_families.insert(antennaModelFamily(m));
  }
  if (product_families.empty() || antex_families.empty()) {
    out.verdict = AntennaModelConsistency::Unknown;
  } else if (product_families.size() == 1 && antex_families == product_families) {
    out.verdict = AntennaModelConsistency::Consistent;
  } else {
    out.verdict = AntennaModelConsistency::Different;
  }
  return out;
}

std::string AntennaModelCheck::models() const {
  return "products " + joined(product_models) + ", ANTEX " + joined(antex_models);
}

std::string AntennaModelCheck::text() const {
  const std::string which = models();
  switch (verdict) {
    case AntennaModelConsistency::Consistent:
      return "satellite antenna model consistent with the products (" + antennaModelFamily(product_models.front()) +
             ": " + which + ")";
    case AntennaModelConsistency::Unknown: return "satellite antenna model not judged (" + which + ")";
    case AntennaModelConsistency::Different:
      return "satellite antenna model differs from the products' (" + which + ")";
  }
  return "unknown";
}

}  // namespace ppp
