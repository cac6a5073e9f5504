// summarizeObservationFile: what ppp_inspect shows for a RINEX observation file.
#include "ppp_bayes_tree/app/inspection.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/types/number_text.h"

namespace ppp {

namespace {

/// Median of epoch differences from a bounded histogram (differences rounded to
/// the millisecond), so that memory stays bounded whatever the file size.
class IntervalHistogram {
 public:
  void add(double dt_s) {
    if (!(dt_s > 0) || dt_s > 1e6) return;
    const auto key = static_cast<long long>(std::llround(dt_s * 1000.0));
    auto it = counts_.find(key);
    if (it != counts_.end()) {
      ++it->second;
    } else if (counts_.size() < 1000) {
      counts_.emplace(key, 1);
    }
    ++total_;
  }
  std::optional<double> median() const {
    if (total_ == 0) return std::nullopt;
    std::size_t seen = 0;
    for (const auto& [key, n] : counts_) {
      seen += n;
      if (2 * seen >= total_) return static_cast<double>(key) / 1000.0;
    }
    return std::nullopt;
  }

 private:
  std::map<long long, std::size_t> counts_;
  std::size_t total_ = 0;
};

void addHeaderFacts(const RinexObsHeader& h, FileSummary& s) {
  auto& f = s.facts;
  f.push_back("marker " + h.marker_name + (h.marker_number.empty() ? "" : " (" + h.marker_number + ")"));
  f.push_back("receiver " + h.receiver_type + " " + h.receiver_version + " #" + h.receiver_number);
  f.push_back("antenna " + h.antenna_type + " " + h.radomeOrNone() + " #" + h.antenna_number);
  if (h.approx_position_ecef_m) {
    const auto& p = *h.approx_position_ecef_m;
    f.push_back("approx position ECEF " + fixedDecimals(p.x(), 4) + " " + fixedDecimals(p.y(), 4) + " " + fixedDecimals(p.z(), 4) + " m");
  }
  if (h.antenna_delta_hen_m) {
    const auto& d = *h.antenna_delta_hen_m;
    f.push_back("antenna delta H/E/N " + fixedDecimals(d.x(), 4) + " " + fixedDecimals(d.y(), 4) + " " + fixedDecimals(d.z(), 4) + " m");
  }
  f.push_back(std::string("epoch time system ") + std::string(timeSystemCode(h.epoch_time_system)));
  if (h.glonass_channel_entries > 0) {
    f.push_back("GLONASS SLOT / FRQ #: " + std::to_string(h.glonass_channels.size()) + " slots");
  }
  if (!h.phase_shifts.empty()) f.push_back("SYS / PHASE SHIFT records: " + std::to_string(h.phase_shifts.size()));
  if (h.leap_seconds) f.push_back("leap seconds " + std::to_string(*h.leap_seconds));
  if (h.interval_s) f.push_back("header interval " + fixedDecimals(*h.interval_s, 3) + " s");
  if (h.isRinex2()) {
    std::string types = "RINEX 2 observation types:";
    for (const auto& t : h.rinex2_obs_types) types += " " + t;
    f.push_back(types);
  }
}

}  // namespace

FileSummary summarizeObservationFile(const std::string& path) {
  FileSummary s;
  s.path = path;
  RinexObsReader reader = RinexObsReader::open(path);
  const RinexObsHeader& h = reader.header();
  s.type = reader.compactRinex() ? "Compact RINEX observation" : "RINEX observation";
  s.version = h.version_text;
  for (int i = 0; i < kNumGnssSystems; ++i) {
    for (const auto& code : h.obs_types[i]) s.signals[static_cast<GnssSystem>(i)].insert(code.toString());
  }
  addHeaderFacts(h, s);

  ObsEpoch epoch;
  IntervalHistogram intervals;
  std::optional<GnssTime> previous;
  std::size_t power_failures = 0, slip_records = 0;
  while (reader.next(epoch)) {
    if (epoch.cycleSlipRecords()) {
      ++slip_records;
      continue;
    }
    if (epoch.powerFailure()) ++power_failures;
    ++s.epoch_count;
    if (!s.first_epoch || epoch.time < *s.first_epoch) s.first_epoch = epoch.time;
    if (!s.last_epoch || epoch.time > *s.last_epoch) s.last_epoch = epoch.time;
    if (previous) intervals.add(epoch.time - *previous);
    previous = epoch.time;
    for (const auto& sat : epoch.satellites) s.satellites[sat.satellite.system].insert(sat.satellite);
  }
  s.interval_s = h.interval_s ? h.interval_s : intervals.median();
  s.facts.push_back("epochs with power failure flag: " + std::to_string(power_failures));
  s.facts.push_back("cycle slip records (flag 6): " + std::to_string(slip_records));
  s.facts.push_back("special event records skipped: " + std::to_string(reader.specialRecordsSkipped()));
  if (reader.epochsBackwards() > 0) s.facts.push_back("epochs going back in time: " + std::to_string(reader.epochsBackwards()));
  if (reader.duplicateEpochs() > 0) s.facts.push_back("duplicate epochs: " + std::to_string(reader.duplicateEpochs()));
  s.report = reader.report();
  return s;
}

}  // namespace ppp
