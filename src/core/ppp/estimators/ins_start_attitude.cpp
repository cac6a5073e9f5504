#include "ppp_bayes_tree/ppp/estimators/ins_start_attitude.h"

#include "ppp_bayes_tree/navigation/ins_alignment.h"

namespace ppp {

InsStartAttitude insStartAttitude(const InsEkfOptions& options, const std::vector<ImuSample>& readings_to_start,
                                  const Eigen::Vector3d& position_ecef_m) {
  InsStartAttitude out;
  if (options.initial_rotation_ecef_body) {
    out.rotation_ecef_body = options.initial_rotation_ecef_body;
    return out;
  }
  if (options.initial_rotation_ned_body) {
    out.rotation_ecef_body = rotationEcefNed(position_ecef_m) * *options.initial_rotation_ned_body;
    return out;
  }
  if (!options.initial_heading_rad) {
    out.problem = "no initial attitude: neither an attitude nor a heading given to the GNSS/INS filter";
    return out;
  }
  const LevelingResult level = levelFromStaticInterval(readings_to_start, position_ecef_m);
  if (level.status != LevelingStatus::Level) {
    out.problem = "no initial attitude: levelling the " + std::to_string(readings_to_start.size()) +
                  " readings up to the start refused: " + levelingStatusText(level.status);
    return out;
  }
  out.rotation_ecef_body =
      rotationEcefNed(position_ecef_m) * rotationNedBody(level.roll_rad, level.pitch_rad, *options.initial_heading_rad);
  return out;
}

Eigen::Vector3d insStartVelocity_ecef_mps(const InsEkfOptions& options, const Eigen::Vector3d& position_ecef_m) {
  return options.initial_velocity_ned_mps
             ? Eigen::Vector3d(rotationEcefNed(position_ecef_m) * *options.initial_velocity_ned_mps)
             : options.initial_velocity_ecef_mps;
}

}  // namespace ppp
