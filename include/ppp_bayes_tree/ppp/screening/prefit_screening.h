#pragma once
// Prefit checks shared by the EKF (ppp_ekf.h) and the smoother (ppp_smoother.h),
// so that both estimators accept and reject the same observations:
//  - usable measurements: finite values, positive sigmas, one per satellite;
//  - the white-clock shift by the median code residual (per system clock);
//  - code outliers by a repeated single-outlier test (Baarda's w-test);
//  - the phase-minus-code innovation test of arcs that already have a bias.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"
#include "ppp_bayes_tree/ppp/screening/screening_options.h"

namespace ppp {

/// Empty when every value an update uses is finite (and sigmas > 0), else the problem.
std::string measurementProblem(const SatelliteMeasurement& m);
/// Whether the Jacobian row has the layout's dimension.
bool matchesLayout(const SatelliteMeasurement& m, const ReceiverStateLayout& layout);

/// The model's used measurements that are finite and unique per satellite;
/// the others are appended to `rejected` with their reason.
std::vector<SatelliteMeasurement> usableMeasurements(const std::vector<SatelliteMeasurement>& used,
                                                     std::vector<RejectedSatellite>& rejected);

/// Median of the code residuals of `system`'s satellites divided by their clock
/// partial: the shift of that (white) receiver clock that centres their code
/// residuals; nullopt when there are none or it is not finite. applyClockShift
/// adds it to the predictions of the system's measurements in `ms`.
std::optional<double> medianCodeClockShift_m(const std::vector<SatelliteMeasurement>& ms,
                                             const ReceiverStateLayout& layout, GnssSystem system);
void applyClockShift(std::vector<SatelliteMeasurement>& ms, const ReceiverStateLayout& layout, GnssSystem system,
                     double shift_m);

/// A code observation rejected by screenCodeOutliers, with its residual
/// against a fit to the other satellites [m].
struct CodeOutlier {
  std::size_t index = 0;  // into the screened vector
  double residual_m = 0.0;
};

/// Prefit code screening (single-outlier test, repeated): weighted least-squares
/// fit of (dx, dy, dz, one dclock per system present) to the code residuals; the suspect is the largest
/// studentised residual w_i = r_i / (sigma_i sqrt(1 - h_ii)) (Baarda's w-test:
/// the satellite whose removal reduces the misfit most); it is rejected when its
/// residual against a fit to the OTHER satellites, r_i / (1 - h_ii), exceeds
/// `threshold_m` (an outlier cannot hide by pulling the fit). Repeated while the
/// redundancy (satellites minus unknowns) is at least 2.
std::vector<CodeOutlier> screenCodeOutliers(const std::vector<SatelliteMeasurement>& ms, double threshold_m,
                                            const ReceiverStateLayout& layout = {});
std::string codeOutlierReason(const CodeOutlier& outlier, double threshold_m);

/// Phase-minus-code innovation of an arc with a bias estimate: phase residual -
/// bias - code residual (geometry, clock and troposphere cancel). Returns the
/// rejection detail when |innovation| > sigmas * sqrt(bias_variance +
/// sigma_code^2 + sigma_phase^2), else nullopt.
std::optional<std::string> phaseInnovationRejection(const SatelliteMeasurement& m, double bias_m,
                                                    double bias_variance_m2, double sigmas);

/// An arc's current bias estimate and its variance, for the phase innovation test.
struct ArcBiasPrior {
  double bias_m = 0.0;
  double variance_m2 = 0.0;
};
/// The estimator's bias of an arc, nullopt when the arc has none (yet).
using ArcBiasLookup = std::function<std::optional<ArcBiasPrior>(ArcId)>;

struct PrefitScreeningResult {
  std::vector<SatelliteMeasurement> kept;  // in the candidates' order
  std::vector<RejectedSatellite> rejected; // with reasons, code outliers first
};

/// The prefit screening of one epoch, as both estimators run it: the code
/// w-test (screenCodeOutliers) over all candidates, then the phase innovation
/// test of the remaining candidates whose arc has a bias (`bias_of`).
PrefitScreeningResult screenPrefit(const std::vector<SatelliteMeasurement>& candidates,
                                   const ScreeningOptions& options, const ArcBiasLookup& bias_of,
                                   const ReceiverStateLayout& layout = {});

}  // namespace ppp
