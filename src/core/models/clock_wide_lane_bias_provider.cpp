#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/bias_bounds.h"
#include "ppp_bayes_tree/types/carrier_frequency.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

std::optional<ClockWideLaneSignals> clockWideLaneSignals(GnssSystem system) {
  static const ClockWideLaneSignals kTable[] = {
      {GnssSystem::GPS, '1', '2', "WP", "WP", "0102"},
      {GnssSystem::Galileo, '1', '5', "CX", "QX", "0105"},
  };
  for (const auto& row : kTable)
    if (row.system == system) return row;
  return std::nullopt;
}

ClockWideLaneBiases parseClockWideLaneBiases(const std::vector<std::string>& comments,
                                             const std::vector<std::size_t>& lines) {
  ClockWideLaneBiases out;
  for (std::size_t i = 0; i < comments.size(); ++i) {
    const std::string& c = comments[i];
    if (c.rfind("WL ", 0) != 0) continue;
    ++out.lines;
    const std::string where =
        (i < lines.size() ? "line " + std::to_string(lines[i]) : "clock header comment " + std::to_string(i + 1)) +
        " \"" + c + "\"";
    const auto refuse = [&](const std::string& why) {
      ++out.refused;
      out.problems.push_back(where + ": " + why);
    };
    std::istringstream in(c);
    std::string tag, sat_text;
    double date[6];
    int count = 0;
    double value = 0.0;
    in >> tag >> sat_text;
    for (double& d : date) in >> d;
    in >> count >> value;
    const auto sat = SatelliteId::parse(sat_text);
    if (!in || !sat || count < 1) {
      refuse("not a wide-lane bias (WL sat date count value)");
      continue;
    }
    if (const auto beyond = wideLaneBiasBeyondBound(value)) {
      refuse(*beyond + ": not used");
      continue;
    }
    std::string pair;  // optional frequency field ("0102", "0105")
    in >> pair;
    const auto signals = clockWideLaneSignals(sat->system);
    if (!pair.empty() && signals && pair != signals->header_pair) {
      refuse("frequency pair " + pair + " is not the " + std::string(systemName(sat->system)) + " pair " +
             signals->header_pair);
      continue;
    }
    out.wide_lane_cycles[*sat] = value;
  }
  return out;
}

namespace {
BiasAnswer absent(const GnssTime& t) {
  BiasAnswer a;
  a.valid_from = t;
  a.valid_until = t;
  return a;
}
}  // namespace

BiasAnswer ClockWideLaneBiasProvider::codeBias(const SatelliteId& sat, const ObservationCode& code,
                                               const GnssTime& t) const {
  const auto signals = clockWideLaneSignals(sat.system);
  if (!signals || !wide_lane_cycles_.count(sat)) return absent(t);
  const bool reference =
      (code.band == signals->band1 && signals->code_attributes1.find(code.attribute) != std::string::npos) ||
      (code.band == signals->band2 && signals->code_attributes2.find(code.attribute) != std::string::npos);
  if (!reference) return absent(t);
  BiasAnswer a;
  a.value_m = 0.0;
  return a;
}

BiasAnswer ClockWideLaneBiasProvider::phaseBias(const SatelliteId& sat, const ObservationCode& code,
                                                const GnssTime& t) const {
  const auto w = wide_lane_cycles_.find(sat);
  const auto signals = clockWideLaneSignals(sat.system);
  if (!signals || w == wide_lane_cycles_.end() || (code.band != signals->band1 && code.band != signals->band2))
    return absent(t);
  const auto f1_hz = carrierFrequency_hz(sat.system, signals->band1), f2_hz = carrierFrequency_hz(sat.system, signals->band2);
  if (!f1_hz || !f2_hz) return absent(t);
  const double f1 = *f1_hz, f2 = *f2_hz;
  // f1 b1 - f2 b2 = s w c and f1^2 b1 = f2^2 b2  =>  b1 = -s w c f2 / (f1 (f1 - f2)).
  const double b1_m = -sign_ * w->second * kSpeedOfLight_mps * f2 / (f1 * (f1 - f2));
  BiasAnswer a;
  a.value_m = code.band == signals->band1 ? b1_m : b1_m * f1 * f1 / (f2 * f2);
  return a;
}

IntegerRecoveryClockBiases readIntegerRecoveryClockBiases(const std::vector<RinexClockHeader>& headers,
                                                          const std::vector<std::string>& clock_files) {
  IntegerRecoveryClockBiases out;
  if (headers.empty()) return out;
  std::map<SatelliteId, double> all;
  bool every_file = true;
  for (std::size_t i = 0; i < headers.size(); ++i) {
    const ClockWideLaneBiases wl = parseClockWideLaneBiases(headers[i].comments, headers[i].comment_lines);
    for (const auto& p : wl.problems) out.problems.push_back(fileBaseName(clock_files[i]) + ": " + p);
    out.lines += wl.lines;
    out.refused += wl.refused;
    every_file = every_file && !wl.wide_lane_cycles.empty();
    all.insert(wl.wide_lane_cycles.begin(), wl.wide_lane_cycles.end());
  }
  if (every_file)
    out.provider = std::make_shared<const ClockWideLaneBiasProvider>(std::move(all), fileBaseName(clock_files.front()));
  return out;
}

std::string IntegerRecoveryClockBiases::whyNone() const {
  if (provider || lines == 0) return {};
  std::string out = refused == lines
                        ? "all " + std::to_string(lines) + " wide-lane lines of the clock header refused"
                        : "a clock file without usable wide-lane lines (" + std::to_string(refused) + " of " +
                              std::to_string(lines) + " refused)";
  if (!problems.empty()) out += " (first: " + problems.front() + ")";
  return out;
}

std::shared_ptr<const ClockWideLaneBiasProvider> integerRecoveryClockBiases(
    const std::vector<RinexClockHeader>& headers, const std::vector<std::string>& clock_files,
    std::vector<std::string>& problems) {
  IntegerRecoveryClockBiases read = readIntegerRecoveryClockBiases(headers, clock_files);
  problems.insert(problems.end(), read.problems.begin(), read.problems.end());
  return read.provider;
}

}  // namespace ppp
