#pragma once
// RecordFilter: which data records a product reader keeps (satellite systems and
// a time window), so that a user of a few hours of one system does not parse a
// day of every system. Records outside are counted in the reader's report
// ("... outside the filter skipped"), never silently dropped.
#include <optional>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct RecordFilter {
  /// Satellite systems to keep; empty keeps every system.
  std::vector<GnssSystem> systems;
  /// Records at or after `first` and at or before `last` (GPST) are kept; unset: no bound.
  std::optional<GnssTime> first, last;

  bool keepsSystem(GnssSystem s) const {
    if (systems.empty()) return true;
    for (GnssSystem k : systems)
      if (k == s) return true;
    return false;
  }
  bool keepsTime(const GnssTime& t) const { return (!first || !(t < *first)) && (!last || !(*last < t)); }
  bool active() const { return !systems.empty() || first || last; }
};

}  // namespace ppp
