#include "ppp_bayes_tree/navigation/imu_coverage.h"

namespace ppp {

std::string imuCoverageProblemText(ImuCoverageProblem problem) {
  switch (problem) {
    case ImuCoverageProblem::None: return "covered";
    case ImuCoverageProblem::NoReadingAtStart: return "no reading at or before the start";
    case ImuCoverageProblem::Gap: return "gap";
  }
  return "unknown";
}

std::string ImuCoverage::text() const {
  switch (problem) {
    case ImuCoverageProblem::None: return {};
    case ImuCoverageProblem::NoReadingAtStart: return "no reading at or before " + start.toString();
    case ImuCoverageProblem::Gap:
      return "gap of " + std::to_string(gap_s) + " s after the reading at " + held_time->toString() + " (at most " +
             std::to_string(max_gap_s) + " s)";
  }
  return imuCoverageProblemText(problem);
}

ImuCoverage imuCoverage(const std::vector<ImuSample>& readings, const GnssTime& start, const GnssTime& end,
                        double max_gap_s) {
  ImuCoverage c;
  c.start = start;
  c.max_gap_s = max_gap_s;
  const auto holdTooLong = [&c, max_gap_s](const GnssTime& held, const GnssTime& until) {
    if (until - held <= max_gap_s) return false;
    c.problem = ImuCoverageProblem::Gap;
    c.held_time = held;
    c.gap_s = until - held;
    return true;
  };
  // 1. The reading held at the start; 2. each hold up to the next reading in the interval; 3. the last one's to the end.
  std::optional<GnssTime> held;
  for (const ImuSample& s : readings) {
    if (s.time - start <= 0.0) {
      held = s.time;
      continue;
    }
    if (s.time - end > 0.0) break;
    if (!held) break;
    if (holdTooLong(*held, s.time)) return c;
    held = s.time;
  }
  if (!held) {
    c.problem = ImuCoverageProblem::NoReadingAtStart;
    return c;
  }
  c.held_to_end = holdTooLong(*held, end);
  return c;
}

}  // namespace ppp
