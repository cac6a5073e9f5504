#include "ppp_bayes_tree/ros/message_conversions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "ppp_bayes_tree/ppp/ambiguity/phase_bias_consistency.h"

namespace ppp_ros {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::int64_t kSecondsPerWeek = 604800;
constexpr std::int64_t kGpsEpochUnix_s = 315964800;  // 1980-01-06 00:00:00 UTC in POSIX seconds
constexpr std::uint8_t kAbsent = ppp_bayes_tree::GnssSignal::FLAG_ABSENT;

/// Physical ranges of incoming observations (beyond: absurd, excluded).
/// Pseudorange: any GNSS orbit up to GEO/IGSO plus a receiver clock offset of
/// up to 1 ms (300 km) either way; phase: the same range in cycles of the
/// longest wavelength plus arbitrary integer offsets of receivers (1e11 cycles);
/// Doppler: +-100 kHz; C/N0: 0..100 dB-Hz.
bool plausible(ppp::ObservableType type, double v, std::string* why) {
  if (!std::isfinite(v)) {
    *why = "non-finite value";
    return false;
  }
  switch (type) {
    case ppp::ObservableType::Pseudorange:
      if (v < 1.0e6 || v > 1.0e8) { *why = "pseudorange outside [1e6, 1e8] m"; return false; }
      return true;
    case ppp::ObservableType::CarrierPhase:
      if (std::abs(v) > 1.0e11) { *why = "carrier phase beyond 1e11 cycles"; return false; }
      return true;
    case ppp::ObservableType::Doppler:
      if (std::abs(v) > 1.0e5) { *why = "Doppler beyond 100 kHz"; return false; }
      return true;
    case ppp::ObservableType::SignalStrength:
      if (v < 0.0 || v > 100.0) { *why = "C/N0 outside [0, 100] dB-Hz"; return false; }
      return true;
    default: return true;
  }
}

std::optional<std::uint8_t> flag(std::uint8_t f) {
  return f == kAbsent || f > 9 ? std::nullopt : std::optional<std::uint8_t>(f);
}
std::uint8_t flag(const std::optional<std::uint8_t>& f) { return f ? *f : kAbsent; }

int typeIndex(ppp::ObservableType t) {
  switch (t) {
    case ppp::ObservableType::Pseudorange: return ppp_bayes_tree::GnssSignal::PSEUDORANGE;
    case ppp::ObservableType::CarrierPhase: return ppp_bayes_tree::GnssSignal::CARRIER_PHASE;
    case ppp::ObservableType::Doppler: return ppp_bayes_tree::GnssSignal::DOPPLER;
    case ppp::ObservableType::SignalStrength: return ppp_bayes_tree::GnssSignal::CN0;
    default: return -1;
  }
}
constexpr std::array<ppp::ObservableType, 4> kSignalTypes{ppp::ObservableType::Pseudorange,
                                                          ppp::ObservableType::CarrierPhase,
                                                          ppp::ObservableType::Doppler,
                                                          ppp::ObservableType::SignalStrength};

double& signalValue(ppp_bayes_tree::GnssSignal& s, int index) {
  switch (index) {
    case 0: return s.pseudorange_m;
    case 1: return s.carrier_phase_cycles;
    case 2: return s.doppler_hz;
    default: return s.cn0_dbhz;
  }
}
double signalValue(const ppp_bayes_tree::GnssSignal& s, int index) {
  return signalValue(const_cast<ppp_bayes_tree::GnssSignal&>(s), index);
}

std::optional<double> finiteOrNone(double v) { return std::isfinite(v) ? std::optional<double>(v) : std::nullopt; }
double valueOrNaN(const std::optional<double>& v) { return v ? *v : kNaN; }

}  // namespace

std::size_t ConversionIssues::total() const {
  std::size_t n = 0;
  for (const auto& [reason, count] : counts) n += count;
  return n;
}

MessageTime toMessageTime(const ppp::GnssTime& t, ppp::TimeSystem system) {
  const double offset = t.offsetToSystem_s(system);  // whole seconds for every system
  const std::int64_t whole = t.wholeSeconds() + static_cast<std::int64_t>(std::llround(offset));
  MessageTime m;
  const std::int64_t week = whole >= 0 ? whole / kSecondsPerWeek : (whole - kSecondsPerWeek + 1) / kSecondsPerWeek;
  m.week = static_cast<std::uint16_t>(week);
  m.seconds_of_week = static_cast<double>(whole - week * kSecondsPerWeek) + t.fraction();
  m.time_system = std::string(ppp::timeSystemCode(system));
  return m;
}

ppp::GnssTime fromMessageTime(std::uint16_t week, double seconds_of_week, const std::string& time_system) {
  const auto system = ppp::parseTimeSystem(time_system);
  if (!system) throw std::invalid_argument("unknown time system '" + time_system + "'");
  if (!std::isfinite(seconds_of_week) || seconds_of_week < 0.0 || seconds_of_week >= kSecondsPerWeek)
    throw std::invalid_argument("seconds of week outside [0, 604800)");
  const double whole_sow = std::floor(seconds_of_week);
  const double fraction = std::round((seconds_of_week - whole_sow) * 1e9) * 1e-9;
  const std::int64_t reading = static_cast<std::int64_t>(week) * kSecondsPerWeek + static_cast<std::int64_t>(whole_sow);
  // reading = GPST + offset(GPST): iterate once for a leap second between the two.
  ppp::GnssTime t = ppp::GnssTime::fromGpsSeconds(reading, fraction);
  for (int i = 0; i < 2; ++i) {
    const double offset = t.offsetToSystem_s(*system);
    t = ppp::GnssTime::fromGpsSeconds(reading - static_cast<std::int64_t>(std::llround(offset)), fraction);
  }
  return t;
}

ros::Time utcStamp(const ppp::GnssTime& t) {
  const std::int64_t utc = t.wholeSeconds() + static_cast<std::int64_t>(std::llround(t.offsetToSystem_s(ppp::TimeSystem::UTC)));
  const auto nsec = static_cast<std::uint32_t>(std::min(999999999.0, std::round(t.fraction() * 1e9)));
  return ros::Time(static_cast<std::uint32_t>(std::max<std::int64_t>(0, utc + kGpsEpochUnix_s)), nsec);
}

ppp::GnssTime fromUtcStamp(const ros::Time& stamp) {
  const std::int64_t utc = static_cast<std::int64_t>(stamp.sec) - kGpsEpochUnix_s;
  const double fraction = stamp.nsec * 1e-9;
  // GPST = UTC - offset(GPST -> UTC): iterate once for a leap second between the two.
  ppp::GnssTime t = ppp::GnssTime::fromGpsSeconds(utc, fraction);
  for (int i = 0; i < 2; ++i) {
    const double offset = t.offsetToSystem_s(ppp::TimeSystem::UTC);
    t = ppp::GnssTime::fromGpsSeconds(utc - static_cast<std::int64_t>(std::llround(offset)), fraction);
  }
  return t;
}

ppp_bayes_tree::GnssObservations toMessage(const ppp::ObsEpoch& epoch, const ppp::RinexObsHeader& header) {
  ppp_bayes_tree::GnssObservations m;
  m.header.stamp = utcStamp(epoch.time);
  m.header.frame_id = "gnss_antenna";
  const MessageTime mt = toMessageTime(epoch.time, header.epoch_time_system);
  m.week = mt.week;
  m.seconds_of_week = mt.seconds_of_week;
  m.time_system = mt.time_system;
  m.epoch_flag = static_cast<std::uint8_t>(epoch.flag);
  m.receiver_clock_offset_s = valueOrNaN(epoch.receiver_clock_offset_s);
  m.marker_name = header.marker_name;
  m.receiver_type = header.receiver_type;
  m.receiver_serial = header.receiver_number;
  m.antenna_type = header.antenna_type;
  m.antenna_radome = header.antenna_radome;
  m.antenna_serial = header.antenna_number;
  const Eigen::Vector3d hen = header.antenna_delta_hen_m.value_or(Eigen::Vector3d::Zero());
  m.antenna_delta_hen_m.x = hen.x();
  m.antenna_delta_hen_m.y = hen.y();
  m.antenna_delta_hen_m.z = hen.z();
  const auto& apx = header.approx_position_ecef_m;
  m.approx_position_ecef_m.x = apx ? apx->x() : kNaN;
  m.approx_position_ecef_m.y = apx ? apx->y() : kNaN;
  m.approx_position_ecef_m.z = apx ? apx->z() : kNaN;
  m.satellites.reserve(epoch.satellites.size());
  for (std::size_t i = 0; i < epoch.satellites.size(); ++i) {
    ppp_bayes_tree::GnssSatelliteObservations s;
    const ppp::SatelliteId sat = epoch.satellites[i].satellite;
    s.satellite = sat.toString();
    s.glonass_channel = ppp_bayes_tree::GnssSatelliteObservations::GLONASS_CHANNEL_UNKNOWN;
    if (sat.system == ppp::GnssSystem::GLONASS) {
      if (auto k = header.glonass_channels.channel(sat.prn)) s.glonass_channel = static_cast<std::int8_t>(*k);
    }
    std::map<std::string, std::size_t> by_signal;  // "1C" -> index in s.signals
    for (const ppp::Observation* o = epoch.begin(i); o != epoch.end(i); ++o) {
      if (!o->value && !o->lli && !o->ssi) continue;  // blank field: nothing to carry
      const int idx = typeIndex(o->code.type);
      if (idx < 0) {
        ppp_bayes_tree::GnssOtherObservation x;
        x.code = o->code.toString();
        x.value = valueOrNaN(o->value);
        x.lli = flag(o->lli);
        x.ssi = flag(o->ssi);
        s.other.push_back(x);
        continue;
      }
      const std::string sig = o->code.signal();
      auto it = by_signal.find(sig);
      if (it == by_signal.end()) {
        ppp_bayes_tree::GnssSignal g;
        g.code = sig;
        g.pseudorange_m = g.carrier_phase_cycles = g.doppler_hz = g.cn0_dbhz = g.lock_time_s = kNaN;
        g.lli.fill(kAbsent);
        g.ssi.fill(kAbsent);
        it = by_signal.emplace(sig, s.signals.size()).first;
        s.signals.push_back(g);
      }
      ppp_bayes_tree::GnssSignal& g = s.signals[it->second];
      signalValue(g, idx) = valueOrNaN(o->value);
      g.lli[idx] = flag(o->lli);
      g.ssi[idx] = flag(o->ssi);
    }
    m.satellites.push_back(std::move(s));
  }
  return m;
}

bool fromMessage(const ppp_bayes_tree::GnssObservations& msg, ppp::RinexObsHeader& layout, ppp::ObsEpoch& epoch,
                 ConversionIssues& issues) {
  epoch.clear();
  epoch.time = fromMessageTime(msg.week, msg.seconds_of_week, msg.time_system);
  epoch.flag = msg.epoch_flag <= 6 ? static_cast<ppp::EpochFlag>(msg.epoch_flag) : ppp::EpochFlag::Ok;
  if (msg.epoch_flag > 6) issues.add("epoch flag above 6 read as 0");
  epoch.receiver_clock_offset_s = finiteOrNone(msg.receiver_clock_offset_s);
  if (auto ts = ppp::parseTimeSystem(msg.time_system)) layout.epoch_time_system = *ts;
  layout.marker_name = msg.marker_name;
  layout.receiver_type = msg.receiver_type;
  layout.receiver_number = msg.receiver_serial;
  layout.antenna_type = msg.antenna_type;
  layout.antenna_radome = msg.antenna_radome == "NONE" ? "" : msg.antenna_radome;
  layout.antenna_number = msg.antenna_serial;
  const Eigen::Vector3d hen(msg.antenna_delta_hen_m.x, msg.antenna_delta_hen_m.y, msg.antenna_delta_hen_m.z);
  layout.antenna_delta_hen_m = hen.allFinite() ? hen : Eigen::Vector3d::Zero();
  const Eigen::Vector3d apx(msg.approx_position_ecef_m.x, msg.approx_position_ecef_m.y, msg.approx_position_ecef_m.z);
  if (apx.allFinite() && apx.norm() > 6.0e6 && apx.norm() < 1.0e8) layout.approx_position_ecef_m = apx;
  else layout.approx_position_ecef_m.reset();

  // 1. Valid satellites and codes; grow the layout.
  struct Item { ppp::ObservationCode code; std::optional<double> value; std::optional<std::uint8_t> lli, ssi; };
  std::vector<std::pair<ppp::SatelliteId, std::vector<Item>>> sats;
  bool changed = false;
  const auto addType = [&](const ppp::SatelliteId& sat, const ppp::ObservationCode& code) {
    auto& types = layout.obs_types[static_cast<int>(sat.system)];
    if (std::find(types.begin(), types.end(), code) == types.end()) {
      types.push_back(code);
      changed = true;
    }
  };
  for (const auto& s : msg.satellites) {
    const auto sat = ppp::SatelliteId::parse(s.satellite);
    if (!sat) {
      issues.add("unknown satellite id '" + s.satellite.substr(0, 8) + "'");
      continue;
    }
    if (sat->system == ppp::GnssSystem::GLONASS &&
        s.glonass_channel != ppp_bayes_tree::GnssSatelliteObservations::GLONASS_CHANNEL_UNKNOWN) {
      const std::optional<int> known = layout.glonass_channels.channel(sat->prn);
      if (!layout.glonass_channels.set(sat->prn, s.glonass_channel)) issues.add("invalid GLONASS channel");
      else if (known != std::optional<int>(s.glonass_channel)) changed = true;  // the signal selection needs it
    }
    std::vector<Item> items;
    for (const auto& g : s.signals) {
      for (const ppp::ObservableType type : kSignalTypes) {
        const int idx = typeIndex(type);
        const double v = signalValue(g, idx);
        const auto lli = flag(g.lli[idx]), ssi = flag(g.ssi[idx]);
        if (std::isnan(v) && !lli && !ssi) continue;
        const auto code = ppp::ObservationCode::parse(std::string(1, static_cast<char>(type)) + g.code);
        if (!code || g.code.size() != 2) {
          issues.add("unknown signal code '" + g.code.substr(0, 8) + "'");
          break;
        }
        std::string why;
        std::optional<double> value;
        if (!std::isnan(v)) {
          if (plausible(type, v, &why)) value = v;
          else issues.add("observation excluded: " + why);
        }
        items.push_back({*code, value, lli, ssi});
        addType(*sat, *code);
      }
    }
    for (const auto& x : s.other) {
      const auto code = ppp::ObservationCode::parse(x.code);
      if (!code) {
        issues.add("unknown observation code '" + x.code.substr(0, 8) + "'");
        continue;
      }
      items.push_back({*code, finiteOrNone(x.value), flag(x.lli), flag(x.ssi)});
      addType(*sat, *code);
    }
    if (std::any_of(sats.begin(), sats.end(), [&](const auto& p) { return p.first == *sat; })) {
      issues.add("satellite listed twice in an epoch (second dropped)");
      continue;
    }
    sats.emplace_back(*sat, std::move(items));
  }
  // 2. Each satellite's slice in the layout's type order (absent: nullopt).
  for (auto& [sat, items] : sats) {
    const auto& types = layout.types(sat.system);
    ppp::SatelliteObservations so;
    so.satellite = sat;
    so.first = static_cast<std::uint32_t>(epoch.observations.size());
    so.count = static_cast<std::uint32_t>(types.size());
    for (const auto& code : types) {
      ppp::Observation o;
      o.code = code;
      for (const auto& it : items)
        if (it.code == code) {
          o.value = it.value;
          o.lli = it.lli;
          o.ssi = it.ssi;
        }
      epoch.observations.push_back(o);
    }
    epoch.satellites.push_back(so);
  }
  return changed;
}

ppp_bayes_tree::PreciseCorrections toMessage(const ppp::CorrectionBatch& batch) {
  ppp_bayes_tree::PreciseCorrections m;
  m.header.stamp = utcStamp(batch.time);
  m.header.frame_id = "earth";
  const MessageTime mt = toMessageTime(batch.time);
  m.week = mt.week;
  m.seconds_of_week = mt.seconds_of_week;
  m.time_system = mt.time_system;
  m.orbit_source = batch.orbit_source;
  m.clock_source = batch.clock_source;
  m.reference_frame = batch.reference_frame;
  m.bias_set = batch.bias_set;
  for (const auto& s : batch.satellites) {
    ppp_bayes_tree::SatelliteCorrection c;
    c.satellite = s.satellite.toString();
    const Eigen::Vector3d p = s.position_ecef_m.value_or(Eigen::Vector3d::Constant(kNaN));
    const Eigen::Vector3d v = s.velocity_ecef_mps.value_or(Eigen::Vector3d::Constant(kNaN));
    c.position_ecef_m.x = p.x();
    c.position_ecef_m.y = p.y();
    c.position_ecef_m.z = p.z();
    c.velocity_ecef_mps.x = v.x();
    c.velocity_ecef_mps.y = v.y();
    c.velocity_ecef_mps.z = v.z();
    c.clock_bias_s = valueOrNaN(s.clock_bias_s);
    c.clock_drift_s_per_s = valueOrNaN(s.clock_drift_s_per_s);
    c.position_sigma_m = valueOrNaN(s.position_sigma_m);
    c.velocity_sigma_mps = valueOrNaN(s.velocity_sigma_mps);
    c.clock_bias_sigma_s = valueOrNaN(s.clock_sigma_s);
    c.clock_drift_sigma_s_per_s = valueOrNaN(s.clock_drift_sigma_s_per_s);
    m.satellites.push_back(c);
  }
  return m;
}

ppp::CorrectionBatch fromMessage(const ppp_bayes_tree::PreciseCorrections& msg, ConversionIssues& issues) {
  ppp::CorrectionBatch b;
  b.time = fromMessageTime(msg.week, msg.seconds_of_week, msg.time_system);
  b.orbit_source = msg.orbit_source;
  b.clock_source = msg.clock_source;
  b.reference_frame = msg.reference_frame;
  b.bias_set = msg.bias_set;
  for (const auto& c : msg.satellites) {
    const auto sat = ppp::SatelliteId::parse(c.satellite);
    if (!sat) {
      issues.add("correction for an unknown satellite '" + c.satellite.substr(0, 8) + "'");
      continue;
    }
    ppp::SatelliteCorrection s;
    s.satellite = *sat;
    const Eigen::Vector3d p(c.position_ecef_m.x, c.position_ecef_m.y, c.position_ecef_m.z);
    const Eigen::Vector3d v(c.velocity_ecef_mps.x, c.velocity_ecef_mps.y, c.velocity_ecef_mps.z);
    // GNSS orbits: 2e7..5e7 m from the geocentre; speeds below 10 km/s; clocks below 1 s.
    if (p.allFinite() && p.norm() > 1.0e7 && p.norm() < 1.0e8) s.position_ecef_m = p;
    else if (!p.hasNaN()) issues.add("absurd satellite position excluded");
    if (s.position_ecef_m && v.allFinite() && v.norm() < 1.0e4) s.velocity_ecef_mps = v;
    if (std::isfinite(c.clock_bias_s) && std::abs(c.clock_bias_s) < 1.0) s.clock_bias_s = c.clock_bias_s;
    else if (!std::isnan(c.clock_bias_s)) issues.add("absurd satellite clock excluded");
    if (std::isfinite(c.clock_drift_s_per_s) && std::abs(c.clock_drift_s_per_s) < 1e-3) s.clock_drift_s_per_s = c.clock_drift_s_per_s;
    s.position_sigma_m = finiteOrNone(c.position_sigma_m);
    s.velocity_sigma_mps = finiteOrNone(c.velocity_sigma_mps);
    s.clock_sigma_s = finiteOrNone(c.clock_bias_sigma_s);
    s.clock_drift_sigma_s_per_s = finiteOrNone(c.clock_drift_sigma_s_per_s);
    b.satellites.push_back(s);
  }
  return b;
}

void addBiases(ppp_bayes_tree::PreciseCorrections& msg, const ppp::SatelliteBiasBatch& biases) {
  msg.ar_bias_source = biases.source;
  for (auto& c : msg.satellites) {
    const auto sat = ppp::SatelliteId::parse(c.satellite);
    const auto it = sat ? biases.biases.find(*sat) : biases.biases.end();
    if (it == biases.biases.end()) continue;
    for (const ppp::ObservableBias& b : it->second) {
      ppp_bayes_tree::ObservableBias m;
      m.observable = b.code.toString();
      m.bias_m = b.bias_m;
      c.biases.push_back(m);
    }
  }
}

ppp::SatelliteBiasBatch biasesFromMessage(const ppp_bayes_tree::PreciseCorrections& msg, ConversionIssues& issues) {
  constexpr double kAbsurdBias_m = 1000.0;  // OSBs are metres to tens of metres
  ppp::SatelliteBiasBatch out;
  out.time = fromMessageTime(msg.week, msg.seconds_of_week, msg.time_system);
  out.source = msg.ar_bias_source;
  if (msg.ar_bias_source.empty()) {
    for (const auto& c : msg.satellites)
      if (!c.biases.empty()) {
        issues.add("satellite biases without ar_bias_source ignored");
        break;
      }
    return out;
  }
  for (const auto& c : msg.satellites) {
    if (c.biases.empty()) continue;
    const auto sat = ppp::SatelliteId::parse(c.satellite);
    if (!sat) continue;  // counted by fromMessage
    std::vector<ppp::ObservableBias> biases;
    for (const auto& b : c.biases) {
      const auto code = ppp::ObservationCode::parse(b.observable);
      if (!code || b.observable.size() != 3 || (code->type != ppp::ObservableType::Pseudorange &&
                                                code->type != ppp::ObservableType::CarrierPhase)) {
        issues.add("satellite bias of an unknown observable '" + b.observable.substr(0, 8) + "' ignored");
        continue;
      }
      if (!std::isfinite(b.bias_m) || std::abs(b.bias_m) >= kAbsurdBias_m) {
        issues.add("absurd satellite bias excluded");
        continue;
      }
      biases.push_back({*code, b.bias_m});
    }
    if (!biases.empty()) out.biases[*sat] = std::move(biases);
  }
  return out;
}

namespace {
/// PreciseCorrections.ar_bias_kind values and the phase information they stand for.
constexpr std::pair<std::uint8_t, ppp::PhaseInformation> kArBiasKinds[] = {
    {ppp_bayes_tree::PreciseCorrections::AR_BIASES_NONE, ppp::PhaseInformation::None},
    {ppp_bayes_tree::PreciseCorrections::AR_BIASES_ANALYSIS_CENTRE_OSB, ppp::PhaseInformation::AnalysisCentreOsb},
    {ppp_bayes_tree::PreciseCorrections::AR_BIASES_INTEGER_RECOVERY_CLOCKS,
     ppp::PhaseInformation::IntegerRecoveryClocks},
    {ppp_bayes_tree::PreciseCorrections::AR_BIASES_SSR, ppp::PhaseInformation::SsrPhaseBiases},
};
}  // namespace

ppp::PhaseInformation phaseInformation(std::uint8_t ar_bias_kind) {
  for (const auto& [kind, phase] : kArBiasKinds)
    if (kind == ar_bias_kind) return phase;
  return ppp::PhaseInformation::None;
}

std::uint8_t arBiasKind(ppp::PhaseInformation phase) {
  for (const auto& [kind, p] : kArBiasKinds)
    if (p == phase) return kind;
  return ppp_bayes_tree::PreciseCorrections::AR_BIASES_NONE;
}

ppp::StreamedProductInfo streamedProductInfo(const ppp_bayes_tree::PreciseCorrections& msg,
                                             const ppp::CorrectionBatch& batch) {
  ppp::StreamedProductInfo info;
  for (const auto& c : batch.satellites)
    if (std::find(info.systems.begin(), info.systems.end(), c.satellite.system) == info.systems.end())
      info.systems.push_back(c.satellite.system);
  info.clock_centre = ppp::analysisCentreOfProductFile(msg.clock_source).value_or("");
  info.antenna_model = msg.antenna_model;
  return info;
}

}  // namespace ppp_ros
