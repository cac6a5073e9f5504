#include "ppp_bayes_tree/evaluation/solution_csv_writer.h"

#include <cmath>
#include <cstdio>

#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/number_text.h"

namespace ppp {
namespace {

}  // namespace

std::string isoTimeText(const GnssTime& time, int decimals) {
  decimals = std::max(0, std::min(decimals, 9));
  const double scale = std::pow(10.0, decimals);
  const GnssTime t = GnssTime::fromGpsSeconds(time.wholeSeconds(), std::round(time.fraction() * scale) / scale);
  const auto c = t.toCalendar(TimeSystem::GPS);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%0*.*f", c.year, c.month, c.day, c.hour, c.minute,
                decimals > 0 ? decimals + 3 : 2, decimals, c.second);
  return buf;
}

SolutionCsvWriter::SolutionCsvWriter(std::ostream& out, std::optional<Eigen::Vector3d> truth_ecef_m)
    : out_(out), truth_ecef_m_(std::move(truth_ecef_m)) {
  out_ << headerRow(truth_ecef_m_.has_value()) << "\n";
}

void SolutionCsvWriter::write(const SolutionEpoch& epoch) { out_ << row(epoch, truth_ecef_m_) << "\n"; }

std::string SolutionCsvWriter::headerRow(bool with_truth) {
  std::string h = "gps_week,tow_s,time_gpst,x_m,y_m,z_m,lat_deg,lon_deg,height_m,";
  if (with_truth) h += "e_err_m,n_err_m,u_err_m,err3d_m,";
  return h + "sigma_e_m,sigma_n_m,sigma_u_m,sats_used,sats_rejected,zwd_m,clock_m,status,integrity";
}

std::string SolutionCsvWriter::row(const SolutionEpoch& e, const std::optional<Eigen::Vector3d>& truth) {
  const auto w = e.time.gpsWeek();
  std::string r = std::to_string(w.week) + "," + csvNumber("%.3f", w.seconds_of_week) + "," + isoTimeText(e.time) + ",";
  const bool has = e.position_ecef_m && e.position_ecef_m->allFinite();
  if (has) {
    const Eigen::Vector3d& p = *e.position_ecef_m;
    const Geodetic g = ecefToGeodetic(p);
    r += csvNumber("%.4f", p.x()) + "," + csvNumber("%.4f", p.y()) + "," + csvNumber("%.4f", p.z()) + ",";
    r += csvNumber("%.9f", g.latitude_rad / kDegToRad) + "," + csvNumber("%.9f", g.longitude_rad / kDegToRad) + "," +
         csvNumber("%.4f", g.height_m) + ",";
  } else {
    r += ",,,,,,";
  }
  if (truth) {
    if (has) {
      const Eigen::Vector3d enu = ecefToEnu(*e.position_ecef_m, *truth);
      r += csvNumber("%.4f", enu.x()) + "," + csvNumber("%.4f", enu.y()) + "," + csvNumber("%.4f", enu.z()) + "," +
           csvNumber("%.4f", enu.norm()) + ",";
    } else {
      r += ",,,,";
    }
  }
  if (has && e.covariance_ecef_m2 && e.covariance_ecef_m2->allFinite()) {
    const Geodetic g = ecefToGeodetic(*e.position_ecef_m);
    const Eigen::Matrix3d R = rotationEnuFromEcef(g.latitude_rad, g.longitude_rad);
    const Eigen::Vector3d var = (R * *e.covariance_ecef_m2 * R.transpose()).diagonal();
    for (int i = 0; i < 3; ++i) r += csvNumber("%.4f", std::sqrt(std::max(var(i), 0.0))) + ",";
  } else {
    r += ",,,";
  }
  r += std::to_string(e.satellites_used) + "," + std::to_string(e.satellites_rejected) + ",";
  r += (e.zwd_m ? csvNumber("%.4f", *e.zwd_m) : std::string()) + ",";
  r += (e.receiver_clock_m ? csvNumber("%.4f", *e.receiver_clock_m) : std::string()) + ",";
  return r + solutionStatusName(e.status) + "," + toString(e.integrity);
}

}  // namespace ppp
