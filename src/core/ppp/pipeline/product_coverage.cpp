#include "ppp_bayes_tree/ppp/pipeline/product_coverage.h"

namespace ppp {
namespace {

/// Tolerance of the comparisons [s]: a product epoch 1 ms off an observation epoch is at it.
constexpr double kCoverageTolerance_s = 1e-3;

std::string timeText(const GnssTime& t) { return t.toString(TimeSystem::GPS, 0); }

std::string kindText(const ProductTimeSpan& p) { return p.kind + " (" + p.files + ")"; }

CoverageFinding notCovered(const ProductTimeSpan& p, const GnssTime& first, const GnssTime& last) {
  const std::string observations = "observations " + timeText(first) + " to " + timeText(last);
  if (!p.first || !p.last)
    return {CoverageVerdict::NotCovered, kindText(p) + ": no record at or near the " + observations +
                                             ": products of another time?"};
  return {CoverageVerdict::NotCovered, kindText(p) + (p.stated_validity ? " valid " : " span ") + timeText(*p.first) +
                                           " to " + timeText(*p.last) + ", " + observations +
                                           ": the products are not of the observations' time"};
}

}  // namespace

CoverageFinding checkProductCoverage(const ProductTimeSpan& p, const GnssTime& first, const GnssTime& last) {
  if (!p.first || !p.last || *p.last - first < -kCoverageTolerance_s || last - *p.first < -kCoverageTolerance_s)
    return notCovered(p, first, last);
  std::string text;
  if (*p.first - first > kCoverageTolerance_s)
    text = kindText(p) + " start at " + timeText(*p.first) + ", observations from " + timeText(first) +
           ": epochs before are not solved";
  if (last - *p.last > kCoverageTolerance_s)
    text += (text.empty() ? "" : "; ") + kindText(p) + " end at " + timeText(*p.last) + ", observations until " +
            timeText(last) + ": epochs after are not solved";
  if (text.empty()) return {};
  return {CoverageVerdict::Partial, text};
}

}  // namespace ppp
