#include "ppp_bayes_tree/ppp/pipeline/product_coverage.h"

#include <stdexcept>

namespace ppp {
namespace {

/// Tolerance of the comparisons [s]: a product epoch 1 ms off an observation epoch is at it.
constexpr double kCoverageTolerance_s = 1e-3;

std::string timeText(const GnssTime& t) { return t.toString(TimeSystem::GPS, 0); }

std::string kindText(const std::string& kind, const std::string& files) { return kind + " (" + files + ")"; }
std::string kindText(const ProductTimeSpan& p) { return kindText(p.kind, p.files); }

CoverageFinding notCovered(const ProductTimeSpan& p, const GnssTime& first, const GnssTime& last) {
  const std::string observations = "observations " + timeText(first) + " to " + timeText(last);
  if (!p.first || !p.last)
    return {CoverageVerdict::NotCovered, kindText(p) + ": no record at or near the " + observations +
                                             ": products of another time?"};
  return {CoverageVerdict::NotCovered, kindText(p) + (p.stated_validity ? " valid " : " span ") + timeText(*p.first) +
                                           " to " + timeText(*p.last) + ", " + observations +
                                           ": the products are not of the observations' time"};
}

/// "G04, E14".
std::string satelliteList(const std::set<SatelliteId>& satellites) {
  std::string out;
  for (const auto& s : satellites) out += (out.empty() ? "" : ", ") + s.toString();
  return out.empty() ? std::string("none") : out;
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

CoverageFinding checkSatelliteCoverage(const ProductSatellites& p, const std::set<SatelliteId>& observed) {
  std::set<SatelliteId> missing;
  for (const auto& s : observed)
    if (!p.carried.count(s)) missing.insert(s);
  if (missing.empty()) return {};
  if (missing.size() == observed.size())
    return {CoverageVerdict::NotCovered, kindText(p.kind, p.files) + " carry none of the observed satellites (observed: " +
                                             satelliteList(observed) + "; carried: " + satelliteList(p.carried) + ")"};
  return {CoverageVerdict::Partial,
          kindText(p.kind, p.files) + " carry no " + satelliteList(missing) + ": those satellites are not used"};
}

void applyCoverageFinding(const CoverageFinding& finding, std::vector<std::string>& notes) {
  if (finding.verdict == CoverageVerdict::NotCovered)
    throw std::runtime_error("products do not cover the observations: " + finding.text);
  if (finding.verdict == CoverageVerdict::Partial) notes.push_back("coverage: " + finding.text);
}

}  // namespace ppp
