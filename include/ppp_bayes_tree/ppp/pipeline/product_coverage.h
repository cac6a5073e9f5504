#pragma once
// The one check that a run's products cover its observations in time, for every
// product kind (orbits, clocks, biases): each kind's span (of the records read
// for the observations' span, or a file's stated validity) against the first and
// last observation epoch. Its findings are notes before solving:
//  - a product that ends before the last (starts after the first) observation:
//    "orbits end at 2020-06-25 23:45:00 GPS, observations until 2020-06-25
//    23:59:30 GPS: epochs after are not solved";
//  - a product with no record near the observations, or valid only at another
//    time ("biases (X.BIA) valid 2021-07-29 ... to 2021-07-30 ..., observations
//    2020-06-25 ... to ...") refuses the run: nothing could be solved, or only
//    with wrong values.
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

/// One product kind's time span. Unset first/last: no record of it near the observations.
struct ProductTimeSpan {
  std::string kind;   // "orbits", "clocks", "biases"
  std::string files;  // the file names, for the text
  std::optional<GnssTime> first, last;
  bool stated_validity = false;  // first/last are the file's stated validity (not records)
};

enum class CoverageVerdict {
  Covered,     // the product spans the observations
  Partial,     // it ends early or starts late: some epochs are not solved
  NotCovered,  // no record near the observations, or valid at another time: refused
};

struct CoverageFinding {
  CoverageVerdict verdict = CoverageVerdict::Covered;
  std::string text;  // empty when covered
};

/// The finding of one kind against the observations' first and last epoch.
CoverageFinding checkProductCoverage(const ProductTimeSpan& product, const GnssTime& observations_first,
                                     const GnssTime& observations_last);

}  // namespace ppp
