#pragma once
// Flight trajectories for the simulator: four built-in UAV profiles of
// increasing dynamics (loiter, survey, figure8, climb) and user trajectories from
// CSV. Positions and velocities are ECEF (WGS 84), flown in the local
// East-North-Up plane of the origin; attitude is the aerospace Z-Y-X sequence
// from North-East-Down to the body frame, in coordinated turns.
// The frames and the profiles' dimensions: doc/evaluation.md, "Trajectories".
// Reference: Stevens B.L., Lewis F.L., Aircraft Control and Simulation, 3rd ed.,
// sec. 2.6 (coordinated turn).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/gnss_time.h"

namespace ppp {

enum class FlightProfile { Loiter, Survey, Figure8, Climb };
const char* flightProfileName(FlightProfile profile);
/// "loiter", "survey", "figure8", "climb"; throws std::invalid_argument otherwise.
FlightProfile parseFlightProfile(const std::string& name);

/// Default origin: near Zimmerwald (46.877 N, 7.465 E, 950 m).
Geodetic defaultSimulationOrigin();

struct TrajectorySample {
  GnssTime time;
  Eigen::Vector3d position_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ecef_mps = Eigen::Vector3d::Zero();
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_rad = 0.0;
};

struct TrajectoryOptions {
  FlightProfile profile = FlightProfile::Loiter;
  GnssTime start;                 // time of the first sample (GPST)
  double duration_s = 1800.0;     // flight length; samples at start + k / rate, k*interval <= duration
  double rate_hz = 1.0;           // 1 or 10 (any positive rate works)
  Geodetic origin = defaultSimulationOrigin();
};

/// Samples a built-in profile.
std::vector<TrajectorySample> generateTrajectory(const TrajectoryOptions& options);

/// Rotation taking a local NED vector into the body frame (x fwd, y right, z down).
Eigen::Matrix3d bodyFromNed(double roll_rad, double pitch_rad, double yaw_rad);
/// Elevation [rad] of a receiver->satellite unit vector (ECEF) above the plane of
/// the body's x-y axes (positive towards the body's "up" = -z), at a position.
double bodyElevation_rad(const TrajectorySample& sample, const Eigen::Vector3d& line_of_sight_ecef);

/// Trajectory CSV (strict: any malformed line throws ParseError naming file and line).
/// Lines starting with '#' and blank lines are ignored. The first other line is the
/// header and must name, in any order, the columns
///   time_s, latitude_deg, longitude_deg, height_m
/// (time since `start` [s], strictly increasing; geodetic WGS 84 position) and may
/// add roll_deg, pitch_deg, yaw_deg (all three or none). Without attitude columns
/// the attitude is derived as a coordinated flight (see above). Velocities are
/// central differences of the positions (one-sided at the ends). At least two rows.
std::vector<TrajectorySample> readTrajectoryCsv(LineSource& source, const GnssTime& start);
std::vector<TrajectorySample> readTrajectoryCsv(const std::string& path, const GnssTime& start);

}  // namespace ppp
