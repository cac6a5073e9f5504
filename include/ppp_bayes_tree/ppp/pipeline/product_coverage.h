#pragma once
// The one check that a run's products cover its observations, in time and in
// satellites, for every product kind (orbits, clocks, biases, a bag's correction
// batches): each kind's span (of the records read for the observations' span, or
// a file's stated validity) against the first and last observation epoch, and
// the satellites it carries against those observed. Its findings are notes
// before solving:
//  - a product that ends before the last (starts after the first) observation:
//    "orbits end at 2020-06-25 23:45:00 GPS, observations until 2020-06-25
//    23:59:30 GPS: epochs after are not solved";
//  - a product with no record near the observations, or valid only at another
//    time ("biases (X.BIA) valid 2021-07-29 ... to 2021-07-30 ..., observations
//    2020-06-25 ... to ...") refuses the run: nothing could be solved, or only
//    with wrong values;
//  - observed satellites a product does not carry: "orbits/clocks (X.SP3, X.CLK)
//    carry no G04, E14: those satellites are not used"; a product that carries
//    none of the observed satellites refuses the run, naming both lists.
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/satellite_id.h"

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

/// The satellites one product kind carries.
struct ProductSatellites {
  std::string kind;   // "orbits/clocks", "biases", "corrections"
  std::string files;  // the file names, for the text
  std::set<SatelliteId> carried;
};

/// The observed satellites (of the systems processed) against those `product`
/// carries: Covered when it carries each (or nothing is observed), Partial when
/// it lacks some (the text names them), NotCovered when it carries none.
CoverageFinding checkSatelliteCoverage(const ProductSatellites& product, const std::set<SatelliteId>& observed);

/// A finding taken into a run: a partial cover becomes the note "coverage: TEXT"
/// in `notes`; none is thrown (std::runtime_error "products do not cover the
/// observations: TEXT").
void applyCoverageFinding(const CoverageFinding& finding, std::vector<std::string>& notes);

}  // namespace ppp
