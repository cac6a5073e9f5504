#pragma once
// Whether the satellite antenna model of the precise products (the ANTEX the
// analysis centre applied when it estimated its orbits and clocks) is the one
// we apply from the ANTEX files, so that integer ambiguities can be fixed.
//
// A satellite z-PCO that differs from the products' by dz reaches the
// ionosphere-free range as dz cos(nadir): nearly constant per satellite over a
// pass, not held by the products' clocks (they hold THEIR model), so it lands in
// the float ambiguity as a constant narrow-lane offset per satellite. Harmless
// for a float solution, it breaks the integer property: ESBC 2020-177 with GRG
// (igs14_2108) products and IGS20 satellite antennas carries offsets of up to
// 0.3 narrow-lane cycle that follow the IGS14 - IGS20 z-PCO differences
// (correlation -0.93, scale 1.03; doc/studies/ar_real_data.md).
//
// The products' model comes from their headers, read by the product assembly
// (io/products/product_antenna_model.h) and handed here as names: the SP3 comment
// "/* PCV:<model>" (e.g. "PCV:IGS14_2108") and the clock header's "SYS / PCVS
// APPLIED" file name (e.g. "igs14_2108.atx"). The ANTEX side comes from the SINEX
// code of each satellite antenna block (e.g. "IGS20_2417"). Models are compared by family:
// the name up to its first '_' or '.', upper case ("IGS14", "IGS20"); the
// week suffix only dates a release of the same frame.
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/models/antex_calibrations.h"  // antennaModelFamily
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

enum class AntennaModelConsistency {
  Consistent,
  Unknown,    // a product header or the ANTEX does not name its model: not judged
  Different,  // the families differ (or the ANTEX mixes families)
};

struct AntennaModelCheck {
  AntennaModelConsistency verdict = AntennaModelConsistency::Unknown;
  std::vector<std::string> product_models;  // as named in the headers, distinct, e.g. "IGS14_2108"
  std::vector<std::string> antex_models;    // SINEX codes of the satellite antennas, distinct
  bool different() const { return verdict == AntennaModelConsistency::Different; }
  /// "products IGS14_2108, ANTEX IGS20_2417" (the names compared).
  std::string models() const;
  /// "satellite antenna model consistent with the products (IGS20: products IGS20_2417, ANTEX IGS20_2423)",
  /// "satellite antenna model differs from the products' (products IGS14_2108, ANTEX IGS20_2417)" or
  /// "satellite antenna model not judged (products: not stated, ANTEX IGS20_2417)".
  std::string text() const;
};

/// The distinct SINEX codes of the satellite antenna blocks of the files ("" codes left out).
std::vector<std::string> satelliteAntennaModels(const AntexCalibrations& antex);

/// The distinct SINEX codes of the blocks that serve `satellites` (at `t`; without
/// a time, each satellite's latest block), as AntexCalibrations picks them: the
/// antennas a run actually uses. Satellites without a block are left out.
std::vector<std::string> usedSatelliteAntennaModels(const AntexCalibrations& antex,
                                                    const std::vector<SatelliteId>& satellites,
                                                    const std::optional<GnssTime>& t);

AntennaModelCheck checkAntennaModelConsistency(const std::vector<std::string>& product_models,
                                               const std::vector<std::string>& antex_models);

}  // namespace ppp
