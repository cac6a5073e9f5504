#pragma once
// Writers of the simulator's files (all deterministic: no wall-clock dates).
//  * RINEX 3.04 observation files (RINEX 3.05 document, sec. 5 and tables
//    A2/A3: header lines A60 + label A20; epoch line ">" 1X,I4,4(1X,I2.2),
//    F11.7,2X,I1,I3; records A3 then per type F14.3,I1 (LLI),I1 (SSI)), for the
//    systems and types of the header;
//  * RINEX clock 3.00 files, AS records only (Ray & Gurtner, "RINEX Extensions
//    to Handle Clock Information" 3.00/3.02: A2,1X,A4,1X,I4,4(1X,I2),1X,F9.6,
//    1X,I2,3X,E19.12);
//  * SP3-c: the existing GPS-only SP3-c writer gpsOnlySp3 (io/products/sp3_writer.h);
//  * truth CSV files (see writeSimulatedFlight).
#include <ostream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/products/rinex_clock_reader.h"
#include "ppp_bayes_tree/io/products/sp3_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

/// RINEX 3.04 observation file. Uses version 3.04 whatever header.version says;
/// writes the header fields the simulator fills (marker, observer/agency,
/// receiver, antenna, approx position, delta H/E/N, obs types, interval, first/
/// last obs, phase shifts, comments). Values with |v| >= 1e10 are written blank.
void writeRinexObs(std::ostream& out, const RinexObsHeader& header, const std::vector<ObsEpoch>& epochs);
std::string rinexObsText(const RinexObsHeader& header, const std::vector<ObsEpoch>& epochs);

/// RINEX clock 3.00 text of the AS records (epochs in GPST).
std::string rinexClockText(const RinexClockFile& clocks);
/// SP3-c text of every system in `sp3` (sp3Copy; GPS only: gpsOnlySp3's text).
std::string sp3Text(const Sp3File& sp3);

/// truth.csv: one row per epoch:
///   time_gpst,gps_week,seconds_of_week,x_m,y_m,z_m,latitude_deg,longitude_deg,height_m,
///   vx_mps,vy_mps,vz_mps,roll_deg,pitch_deg,yaw_deg,zwd_m,clock_m,satellites
void writeTruthEpochsCsv(std::ostream& out, const SimulatedFlight& flight);
/// truth_arcs.csv: one row per epoch and tracked satellite:
///   seconds_of_week,satellite,arc,bias_if_m,n1_cycles,n2_cycles,elevation_deg,body_elevation_deg
void writeTruthArcsCsv(std::ostream& out, const SimulatedFlight& flight);
/// arcs.csv: one row per arc: arc,satellite,first_sow,last_sow,epochs,n1,n2,bias_if_m,after_phase_break
/// breaks.csv: one row per injected slip: satellite,last_tracked_sow,reacquired_sow,previous_arc,new_arc,
///   min_body_elevation_deg,max_roll_deg
void writeArcListCsv(std::ostream& out, const SimulatedFlight& flight);
void writeBreaksCsv(std::ostream& out, const SimulatedFlight& flight);
/// imu.csv: the plain IMU CSV that io/imu/imu_csv_reader.h reads (doc/gnss_ins.md):
///   # gps_week,seconds_of_week,fx,fy,fz,wx,wy,wz
/// seconds of week with 9 decimals, readings [m/s^2, rad/s] with 17 significant
/// digits (they read back to the same doubles).
void writeImuCsv(std::ostream& out, const std::vector<ImuSample>& samples);
/// imu_bias.csv: the true bias at each reading:
///   gps_week,seconds_of_week,ba_x,ba_y,ba_z,bg_x,bg_y,bg_z [m/s^2, rad/s]
void writeImuBiasCsv(std::ostream& out, const SimulatedImu& imu);

/// Writes into `directory` (created when missing): <marker>.obs (RINEX 3.04),
/// products.sp3 / products.clk (truth + product error), truth.sp3 / truth.clk,
/// truth.csv, truth_arcs.csv, arcs.csv, breaks.csv, parameters.txt, and with
/// IMU readings (config.imu.enabled) imu.csv and imu_bias.csv. Returns the
/// paths written. Throws std::runtime_error when a file cannot be written.
std::vector<std::string> writeSimulatedFlight(const SimulatedFlight& flight, const std::string& directory);

}  // namespace ppp
