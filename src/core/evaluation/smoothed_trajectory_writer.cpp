#include "ppp_bayes_tree/evaluation/smoothed_trajectory_writer.h"

#include <cmath>

#include "ppp_bayes_tree/evaluation/solution_csv_writer.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/types/constants.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/number_text.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
SmoothedTrajectoryWriter::SmoothedTrajectoryWriter(const std::string& path)
    : file_(std::make_unique<std::ofstream>(path, std::ios::out | std::ios::trunc)), path_(path) {
  if (!*file_) throw FileOpenError("cannot create the smoothed trajectory file " + path);
  out_ = file_.get();
  *out_ << headerRow() << "\n" << std::flush;
}

SmoothedTrajectoryWriter::SmoothedTrajectoryWriter(std::ostream& out) : out_(&out), path_("(stream)") {
  *out_ << headerRow() << "\n" << std::flush;
}

bool SmoothedTrajectoryWriter::write(const SmoothedEpoch& epoch) {
  if (last_time_ && !(*last_time_ < epoch.time)) {
    ++refused_;
    last_problem_ = format("%s: state x%u at %s refused: not after the last row (%s)", path_.c_str(), epoch.index,
                           isoTimeText(epoch.time).c_str(), isoTimeText(*last_time_).c_str());
    return false;
  }
  *out_ << row(epoch) << "\n" << std::flush;
  last_time_ = epoch.time;
  ++rows_;
  return true;
}

std::string SmoothedTrajectoryWriter::headerRow() {
  return "gps_week,tow_s,time_gpst,x_m,y_m,z_m,lat_deg,lon_deg,height_m,zwd_m,clock_m,state_index";
}

std::string SmoothedTrajectoryWriter::row(const SmoothedEpoch& e) {
  const auto w = e.time.gpsWeek();
  std::string r = std::to_string(w.week) + "," + csvNumber("%.3f", w.seconds_of_week) + "," + isoTimeText(e.time) + ",";
  const Eigen::Vector3d& p = e.state.position_ecef_m;
  if (p.allFinite()) {
    const Geodetic g = ecefToGeodetic(p);
    r += csvNumber("%.4f", p.x()) + "," + csvNumber("%.4f", p.y()) + "," + csvNumber("%.4f", p.z()) + ",";
    r += csvNumber("%.9f", g.latitude_rad / kDegToRad) + "," + csvNumber("%.9f", g.longitude_rad / kDegToRad) + "," +
         csvNumber("%.4f", g.height_m) + ",";
  } else {
    r += ",,,,,,";
  }
  r += csvNumber("%.4f", e.state.zwd_m) + "," + csvNumber("%.4f", e.state.referenceClock_m()) + ",";
  return r + std::to_string(e.index);
}

}  // namespace ppp
