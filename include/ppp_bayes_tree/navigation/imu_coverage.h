#pragma once
// ImuCoverage: whether IMU readings cover an interval [start, end] that an
// estimator integrates through (the GNSS/INS EKF's propagation, the GNSS/INS
// smoother's preintegration, ImuPreintegration::integrateBetween). Each reading
// holds from its time to the next one's (the last one to `end`), so the readings
// cover the interval when
//   - one of them is at or before `start` (it holds at `start`), and
//   - no reading that holds within [start, end] holds longer than max_gap_s: the
//     time from it to the next reading, or to `end` for the last one, is at most
//     max_gap_s (a hold begun before `start` counts whole).
// Readings after `end` do not count; they may be given.
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/navigation/imu_sample.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

enum class ImuCoverageProblem {
  None,              ///< the readings cover the interval
  NoReadingAtStart,  ///< no reading at or before the interval's start
  Gap,               ///< a reading holds longer than max_gap_s
};
/// "covered", "no reading at or before the start", "gap".
std::string imuCoverageProblemText(ImuCoverageProblem problem);

/// The verdict on one interval, with what the text needs.
struct ImuCoverage {
  ImuCoverageProblem problem = ImuCoverageProblem::None;
  GnssTime start;                     ///< the interval's start
  double max_gap_s = 0.0;             ///< the longest hold allowed [s]
  std::optional<GnssTime> held_time;  ///< Gap: the reading that holds too long
  double gap_s = 0.0;                 ///< Gap: how long it holds [s]
  /// Gap: the hold lasts to the interval's end (no later reading in it yet); otherwise
  /// a later reading ends it, and with the readings in time order no reading can
  /// close the gap any more.
  bool held_to_end = false;

  bool covered() const { return problem == ImuCoverageProblem::None; }
  /// Why not covered ("no reading at or before <start>", "gap of <gap> s after the
  /// reading at <time> (at most <max> s)"); empty when covered.
  std::string text() const;
};

/// The coverage of [start, end] by `readings` (in time order), each held to the next one's time.
ImuCoverage imuCoverage(const std::vector<ImuSample>& readings, const GnssTime& start, const GnssTime& end,
                        double max_gap_s);

}  // namespace ppp
