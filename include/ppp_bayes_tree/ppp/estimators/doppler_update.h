#pragma once
// DopplerUpdate: what a GNSS/INS estimator's Doppler velocity update did at an
// epoch (doppler_velocity.h solves the antenna velocity from the range rates; the
// estimator then updates its velocity with it or refuses the innovation). Part of
// the InertialState the estimators report (inertial_state.h), written to
// ppp_solve's attitude file.
#include <Eigen/Core>
#include <optional>

#include "ppp_bayes_tree/ppp/model/doppler_velocity.h"

namespace ppp {

enum class DopplerOutcome { NotTried, Applied, NoVelocity, InnovationRefused };

/// "applied", "no_velocity", "innovation_refused" or "not_tried".
const char* dopplerOutcomeText(DopplerOutcome outcome);

struct DopplerUpdate {
  DopplerOutcome outcome = DopplerOutcome::NotTried;
  int satellites = 0;  ///< in the velocity solution
  int rejected = 0;    ///< by its outlier screen
  DopplerVelocityStatus velocity_status = DopplerVelocityStatus::TooFewSatellites;
  double innovation_chi2 = 0.0;                       ///< the update's normalised innovation square
  std::optional<Eigen::Vector3d> velocity_ecef_mps;  ///< the Doppler's antenna velocity, when solved
};

}  // namespace ppp
