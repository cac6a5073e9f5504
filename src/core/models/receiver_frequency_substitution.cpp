#include "ppp_bayes_tree/models/receiver_frequency_substitution.h"

namespace ppp {

namespace {

// GPS carriers: L1 1575.42, L2 1227.60, L5 1176.45 MHz (IS-GPS-200, IS-GPS-705).
// Other carriers: Galileo OS SIS ICD; GLONASS ICD (FDMA centre, k = 0);
// BeiDou ICDs (B1I, B1C, B2a, B2b, B2a+b, B3I); IS-QZSS.
constexpr std::array<GpsStandIn, 17> kTable{{
    {GnssSystem::Galileo, 1, "E1", 1575.42, {1, 0}},
    {GnssSystem::Galileo, 5, "E5a", 1176.45, {5, 2}},
    {GnssSystem::Galileo, 7, "E5b", 1207.14, {2, 0}},
    {GnssSystem::Galileo, 8, "E5", 1191.795, {5, 2}},
    {GnssSystem::Galileo, 6, "E6", 1278.75, {2, 0}},
    {GnssSystem::GLONASS, 1, "G1", 1602.0, {1, 0}},
    {GnssSystem::GLONASS, 2, "G2", 1246.0, {2, 0}},
    {GnssSystem::BeiDou, 1, "B1C", 1575.42, {1, 0}},
    {GnssSystem::BeiDou, 2, "B1I", 1561.098, {1, 0}},
    {GnssSystem::BeiDou, 5, "B2a", 1176.45, {5, 2}},
    {GnssSystem::BeiDou, 7, "B2b", 1207.14, {2, 0}},
    {GnssSystem::BeiDou, 8, "B2a+b", 1191.795, {5, 2}},
    {GnssSystem::BeiDou, 6, "B3I", 1268.52, {2, 0}},
    {GnssSystem::QZSS, 1, "L1", 1575.42, {1, 0}},
    {GnssSystem::QZSS, 2, "L2", 1227.60, {2, 0}},
    {GnssSystem::QZSS, 5, "L5", 1176.45, {5, 2}},
    {GnssSystem::QZSS, 6, "L6", 1278.75, {2, 0}},
}};

std::string signalName(GnssSystem system, int frequency) {
  if (system == GnssSystem::GPS) return gpsSignalName(frequency);
  const GpsStandIn* row = gpsStandIn(system, frequency);
  if (row != nullptr) return std::string(row->signal);
  return std::string(1, systemLetter(system)) + (frequency < 10 ? "0" : "") + std::to_string(frequency);
}

bool holdsSystem(const AntennaCalibration& receiver, GnssSystem system) {
  for (const auto& f : receiver.frequencies)
    if (f.system == system) return true;
  return false;
}

}  // namespace

std::string_view receiverFrequencySubstitutionName(ReceiverFrequencySubstitution policy) {
  switch (policy) {
    case ReceiverFrequencySubstitution::Gps: return "gps";
    case ReceiverFrequencySubstitution::None: return "none";
  }
  return "?";
}

const std::array<GpsStandIn, 17>& gpsStandInTable() { return kTable; }

const GpsStandIn* gpsStandIn(GnssSystem system, int frequency) {
  for (const auto& row : kTable)
    if (row.system == system && row.frequency == frequency) return &row;
  return nullptr;
}

std::string gpsSignalName(int frequency) {
  switch (frequency) {
    case 1: return "L1";
    case 2: return "L2";
    case 5: return "L5";
  }
  return "G" + std::string(frequency < 10 ? "0" : "") + std::to_string(frequency);
}

ReceiverFrequencyLookup receiverFrequencyCalibration(const AntennaCalibration& receiver, GnssSystem system,
                                                     int frequency, ReceiverFrequencySubstitution policy) {
  ReceiverFrequencyLookup out;
  out.calibration = receiver.frequency(system, frequency);
  if (out.calibration != nullptr || policy == ReceiverFrequencySubstitution::None) return out;
  const GpsStandIn* row = gpsStandIn(system, frequency);
  if (row == nullptr) return out;
  for (const int gps : row->gps_frequencies) {
    if (gps == 0) continue;
    out.calibration = receiver.frequency(GnssSystem::GPS, gps);
    if (out.calibration != nullptr) {
      out.substituted = true;
      return out;
    }
  }
  return out;
}

std::string receiverSubstitutionNote(const AntennaCalibration& receiver, GnssSystem system, int frequency1,
                                     const ReceiverFrequencyLookup& lookup1, int frequency2,
                                     const ReceiverFrequencyLookup& lookup2) {
  std::string gps, own;
  for (const auto& [frequency, lookup] : {std::pair{frequency1, lookup1}, std::pair{frequency2, lookup2}}) {
    if (!lookup.substituted || lookup.calibration == nullptr) continue;
    gps += (gps.empty() ? "" : "/") + gpsSignalName(lookup.calibration->frequency);
    own += (own.empty() ? "" : "/") + signalName(system, frequency);
  }
  const std::string what = holdsSystem(receiver, system) ? std::string(systemName(system)) + " " + own
                                                         : std::string(systemName(system));
  return "receiver antenna " + receiver.label() + ": no " + what + " calibration, GPS " + gps +
         " values used for " + own + " (measurement_model.corrections.receiver_frequency_substitution: gps)";
}

}  // namespace ppp
