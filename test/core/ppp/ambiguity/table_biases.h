#pragma once
// TableBiases: a BiasProvider with fixed per-satellite, per-signal OSBs [m]
// (code and phase alike), for the synthetic ambiguity-resolution tests.
#include <map>
#include <string>
#include <utility>

#include "ppp_bayes_tree/models/bias_provider.h"

namespace ppp {

class TableBiases : public BiasProvider {
 public:
  std::map<std::pair<SatelliteId, std::string>, double> table;  // (satellite, RINEX code) -> bias [m]
  BiasAnswer codeBias(const SatelliteId& s, const ObservationCode& c, const GnssTime&) const override {
    return find(s, c);
  }
  BiasAnswer phaseBias(const SatelliteId& s, const ObservationCode& c, const GnssTime&) const override {
    return find(s, c);
  }
  std::string describeSource() const override { return "table"; }

 private:
  BiasAnswer find(const SatelliteId& s, const ObservationCode& c) const {
    const auto it = table.find({s, c.toString()});
    BiasAnswer a;
    if (it != table.end()) a.value_m = it->second;
    return a;
  }
};

}  // namespace ppp
