#include "ppp_bayes_tree/app/inspection.h"

#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/app/stream_inspection.h"
#include "ppp_bayes_tree/io/products/antex_reader.h"
#include "ppp_bayes_tree/io/products/bias_sinex_reader.h"
#include "ppp_bayes_tree/io/products/blq_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_nav_reader.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/io/transport/file_type.h"
#include "ppp_bayes_tree/models/precise_ephemeris.h"
#include "ppp_bayes_tree/models/product_sanity.h"

namespace ppp {

FileSummary Inspection::add(const std::string& path) {
  switch (detectFileType(path)) {
    case GnssFileType::RinexObservation:
    case GnssFileType::CompactRinexObservation:
      observations_.push_back(summarizeObservationFile(path));
      return observations_.back();
    case GnssFileType::Sp3: {
      orbits_.push_back(readSp3(path));
      FileSummary summary = summarizeSp3(orbits_.back(), path);
      // A single bad value passes the format checks: the leave-one-out orbit check finds it.
      for (const auto& o : findOrbitOutliers(orbits_.back())) summary.report.addProblem(0, o.describe());
      return summary;
    }
    case GnssFileType::RinexClock: {
      clocks_.push_back(readRinexClock(path));
      FileSummary summary = summarizeClock(clocks_.back(), path);
      for (const auto& o : findClockOutliers(clocks_.back())) summary.report.addProblem(0, o.describe());
      return summary;
    }
    case GnssFileType::RinexNavigation:
      return summarizeNavFile(path);
    case GnssFileType::Antex:
      return summarizeAntexFile(path);
    case GnssFileType::BiasSinex:
      return summarizeBiasSinexFile(path);
    case GnssFileType::Blq:
      return summarizeBlqFile(path);
    case GnssFileType::Rtcm3Stream:
    case GnssFileType::UbxStream:
      return summarizeStreamFile(path);
    case GnssFileType::RinexMeteo:
      throw std::runtime_error("RINEX meteorological files are recognised but not read by this project");
    case GnssFileType::Unknown:
      break;
  }
  throw std::runtime_error("not a recognised GNSS file (RINEX obs/nav/clock, CRX, SP3, ANTEX, Bias-SINEX, BLQ)");
}

std::string Inspection::coverageReport() const {
  if (observations_.empty() || (orbits_.empty() && clocks_.empty())) return {};
  PreciseEphemeris products;
  for (const auto& f : orbits_) products.addOrbits(f);
  for (const auto& f : clocks_) products.addClocks(f);

  std::set<GnssSystem> product_systems;
  for (const auto& sat : products.orbitSatellites()) product_systems.insert(sat.system);
  for (const auto& sat : products.clockSatellites()) product_systems.insert(sat.system);

  std::ostringstream os;
  for (const auto& obs : observations_) {
    os << "== coverage of " << obs.path << " by " << orbits_.size() << " orbit and " << clocks_.size()
       << " clock file(s)\n";
    if (!obs.first_epoch || !obs.last_epoch) {
      os << "  the observation file has no epochs\n\n";
      continue;
    }
    std::set<SatelliteId> needed;
    for (const auto& [system, sats] : obs.satellites) {
      if (product_systems.count(system) == 0) {
        os << "  " << systemName(system) << ": " << sats.size()
           << " satellite(s) observed, none in the products (system not carried)\n";
        continue;
      }
      needed.insert(sats.begin(), sats.end());
    }
    const double interval_s = obs.interval_s.value_or(30.0);
    const ProductCoverage coverage =
        checkCoverage(products, *obs.first_epoch, *obs.last_epoch, interval_s, needed);
    for (const auto& line : coverage.describe()) os << "  " << line << "\n";
    os << "  verdict: "
       << (coverage.complete() ? "the products cover every observed satellite of their systems"
                               : "the products do NOT fully cover the observations (see above)")
       << "\n\n";
  }
  return os.str();
}

}  // namespace ppp
