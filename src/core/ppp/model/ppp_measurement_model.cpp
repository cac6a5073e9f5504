#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/models/ocean_loading.h"
#include "ppp_bayes_tree/models/phase_windup.h"
#include "ppp_bayes_tree/models/relativity.h"
#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/models/satellite_eclipse.h"
#include "ppp_bayes_tree/models/yaw_manoeuvre.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"
#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/models/solid_earth_tide.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/models/troposphere.h"
#include "ppp_bayes_tree/models/troposphere_gradient.h"
#include "ppp_bayes_tree/types/frames.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// ANTEX frequency number of a RINEX band (ANTEX 1.4: G01/G02/G05, E01/E05...).
int antexFrequency(char band) { return band - '0'; }

/// IF-combined value of a per-frequency quantity, or nullopt when either is missing.
std::optional<double> combine(const std::optional<double>& v1, const std::optional<double>& v2,
                              const IonosphereFreeCoefficients& k) {
  if (!v1 || !v2) return std::nullopt;
  return ionosphereFree(*v1, *v2, k);
}

/// The satellite clock at the nominal emission time (t_rx minus the code's travel
/// time) and the orbit at the emission time corrected by that clock: the first step
/// of the full and of the start model. Without them the satellite is `reject`ed
/// (NoClock / NoOrbit, with the source's detail) and there is no value.
template <typename Emission, typename Reject>
std::optional<Emission> ephemerisAtEmission(const EphemerisSource& ephemeris, const SatelliteId& sat,
                                            const GnssTime& t_rx, double code_m, Reject&& reject) {
  const GnssTime t_nominal = t_rx - code_m / kSpeedOfLight_mps;
  const EphemerisAnswer<EphemerisClock> clock = ephemeris.satelliteClock(sat, t_nominal);
  if (!clock.ok()) {
    reject(RejectionReason::NoClock, "no clock: " + clock.detail);
    return std::nullopt;
  }
  const EphemerisAnswer<EphemerisOrbit> orbit = ephemeris.satelliteOrbit(sat, t_nominal - clock.value->clock_bias_s);
  if (!orbit.ok()) {
    reject(RejectionReason::NoOrbit, "no orbit: " + orbit.detail);
    return std::nullopt;
  }
  return Emission{*clock.value, *orbit.value};
}

}  // namespace

std::string_view receiverAntennaPolicyName(ReceiverAntennaPolicy policy) {
  switch (policy) {
    case ReceiverAntennaPolicy::Required: return "required";
    case ReceiverAntennaPolicy::Warn: return "warn";
    case ReceiverAntennaPolicy::Off: return "off";
  }
  return "?";
}

PppMeasurementModel::PppMeasurementModel(const EphemerisSource& ephemeris,
                                         std::shared_ptr<const AntennaCalibrationProvider> antennas,
                                         const ReceiverAntenna& receiver_antenna,
                                         const OceanLoadingCoefficients* ocean_loading,
                                         MeasurementModelOptions options)
    : ephemeris_(ephemeris),
      antennas_(std::move(antennas)),
      receiver_antenna_(receiver_antenna),
      options_(options),
      satellite_cache_(static_cast<std::size_t>(kNumGnssSystems) * 100),
      emission_memo_(static_cast<std::size_t>(kNumGnssSystems) * 100),
      l1_reference_without_calibration_(static_cast<std::size_t>(kNumGnssSystems) * 100, 0) {
  if (ocean_loading != nullptr) ocean_loading_ = *ocean_loading;
  if (antennas_) {
    const ReceiverCalibrationLookup r = antennas_->receiver(receiver_antenna_);
    receiver_calibration_ = r.calibration;
    receiver_source_ = r.source;
  } else {
    receiver_source_ = "receiver " + receiver_antenna_.name() + ": no antenna calibrations given";
  }
  if (receiver_calibration_ == nullptr && options_.receiver_antenna == ReceiverAntennaPolicy::Warn) {
    warnReceiverAntenna("receiver antenna " + receiver_antenna_.name() +
                        (antennas_ ? " not found in any ANTEX file" : ": no antenna calibrations given") +
                        ": receiver PCO/PCV not applied (DELTA H/E/N applied; "
                        "measurement_model.corrections.receiver_antenna: warn)");
  }
}

std::vector<std::string> PppMeasurementModel::satelliteReferenceNotes() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < l1_reference_without_calibration_.size(); ++i) {
    const std::size_t n = l1_reference_without_calibration_[i];
    if (n == 0) continue;
    out.push_back(SatelliteId{static_cast<GnssSystem>(i / 100), static_cast<int>(i % 100)}.toString() +
                  ": orbit at the L1 antenna phase centre but no satellite antenna calibration (ANTEX) for it: the "
                  "ionosphere-free - L1 PCO difference taken as zero in " +
                  std::to_string(n) + " satellite-epoch(s)");
  }
  return out;
}

void PppMeasurementModel::warnReceiverAntenna(std::string text) const {
  for (const auto& w : receiver_warnings_)
    if (w == text) return;
  receiver_warnings_.push_back(std::move(text));
}

std::vector<std::string> PppMeasurementModel::antennaSources() const {
  std::vector<std::string> out{receiver_source_};
  for (std::size_t i = 0; i < satellite_cache_.size(); ++i) {
    const auto& c = satellite_cache_[i];
    if (!c.looked_up || c.calibration == nullptr) continue;
    out.push_back("satellite " + c.calibration->label() + ": " + c.source);
  }
  return out;
}

template <typename Reject>
std::optional<PppMeasurementModel::EmissionEphemeris> PppMeasurementModel::emissionEphemeris(
    const SatelliteId& sat, const GnssTime& t_rx, double code_m, Reject&& reject) const {
  EmissionMemo& memo = emission_memo_[static_cast<std::size_t>(sat.index())];
  if (memo.valid && memo.t_rx == t_rx && memo.code_m == code_m) return memo.value;
  memo.valid = false;
  const std::optional<EmissionEphemeris> e =
      ephemerisAtEmission<EmissionEphemeris>(ephemeris_, sat, t_rx, code_m, std::forward<Reject>(reject));
  if (e) memo = EmissionMemo{true, t_rx, code_m, *e};
  return e;
}

const AntennaCalibration* PppMeasurementModel::satelliteCalibration(const SatelliteId& sat,
                                                                    const GnssTime& t) const {
  auto& c = satellite_cache_[static_cast<std::size_t>(sat.index())];
  if (c.looked_up && (!c.from || !(t < *c.from)) && (!c.until || !(*c.until < t))) return c.calibration;
  c = SatelliteAntennaCache{};
  c.looked_up = true;
  if (antennas_) {
    const SatelliteCalibrationLookup found = antennas_->satellite(sat, t);
    if (found.calibration != nullptr) {
      c.calibration = found.calibration;
      c.source = found.source;
      c.from = found.calibration->valid_from;
      c.until = found.calibration->valid_until;
    }
  }
  if (c.calibration == nullptr) c.from = c.until = t;  // absent: retry at the next epoch
  return c.calibration;
}

std::optional<Eigen::Vector3d> PppMeasurementModel::receiverPcoIonosphereFree_m(GnssSystem system, int frequency1,
                                                                                 int frequency2, double f1_hz,
                                                                                 double f2_hz) const {
  if (receiver_calibration_ == nullptr) return std::nullopt;
  const auto policy = options_.receiver_frequency_substitution;
  const auto* a = receiverFrequencyCalibration(*receiver_calibration_, system, frequency1, policy).calibration;
  const auto* b = receiverFrequencyCalibration(*receiver_calibration_, system, frequency2, policy).calibration;
  if (a == nullptr || b == nullptr) return std::nullopt;
  return ionosphereFreeOffset(a->pco_m, b->pco_m, ionosphereFreeCoefficients(f1_hz, f2_hz));
}

/// Step 1: the terms common to every satellite of the epoch.
struct PppMeasurementModel::EpochTerms {
  GnssTime t_rx;
  Eigen::Vector3d marker = Eigen::Vector3d::Zero();  // the linearisation point
  Geodetic geo;
  Eigen::Matrix3d enu_from_ecef = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d ecef_from_enu = Eigen::Matrix3d::Identity();
  SunMoonPositions sun_moon;
  Eigen::Vector3d station_offset = Eigen::Vector3d::Zero();  // marker -> ARP, ECEF
  ReceiverAntennaAxes receiver_axes;
  SurfaceMeteo meteo;
  TroposphereDelays hopfield_zenith;
  double zhd_m = 0.0;
  double zhd_rate = 0.0;  // d ZHD / d h [m/m]
  // zwd_at_ellipsoid: the wet zenith delay at the receiver per metre at the
  // ellipsoid, w(h) / w(0), and its relative change d ln(w) / d h [1/m].
  double wet_height_ratio = 1.0;
  double wet_height_log_rate_per_m = 0.0;
  Eigen::Vector3d up_ecef = Eigen::Vector3d::UnitZ();
  double day_of_year = 0.0;
  double mjd = 0.0;
};

/// Step 2: per system and frequency pair, computed on first use (GLONASS FDMA:
/// again for each satellite whose channel differs from the last one's).
struct PppMeasurementModel::SystemTerms {
  bool done = false;
  bool ok = false;
  std::string missing;
  IonosphereFreeCoefficients k;
  double windup_wavelength_m = 0.0;
  double sigma_factor = 1.0;
  Eigen::Vector3d receiver_apc_ecef = Eigen::Vector3d::Zero();  // marker -> antenna phase centre
  const FrequencyCalibration* r1 = nullptr;
  const FrequencyCalibration* r2 = nullptr;
  char band1 = '1', band2 = '2';
  double frequency1_hz = 0.0, frequency2_hz = 0.0;
};

/// Steps 3-8: what one satellite's evaluation carries from step to step.
struct PppMeasurementModel::SatelliteEvaluation {
  SatelliteEvaluation(const DualFrequencyObservation& observation, const SystemTerms& system, ArcId arc_id,
                      const ObservedIonosphereFree& observed)
      : o(observation), st(system), arc(arc_id), code_if_m(observed.code_m), phase_if_m(observed.phase_m) {}

  const DualFrequencyObservation& o;
  const SystemTerms& st;
  ArcId arc;
  int receiver_clock = -1;  // the column of the satellite's system clock
  // 3. Observed IF combinations, receiver antenna phase centre.
  double code_if_m = 0.0;
  double phase_if_m = 0.0;
  Eigen::Vector3d receiver_apc = Eigen::Vector3d::Zero();
  // 4. The satellite at emission.
  EphemerisClock clock;
  EphemerisOrbit orbit;
  SatelliteBodyAxes axes;
  Eigen::Vector3d apc_tx = Eigen::Vector3d::Zero();                 // IF phase centre at emission
  Eigen::Vector3d reference_offset_ecef = Eigen::Vector3d::Zero();  // added to the orbit to reach it
  const FrequencyCalibration* s1 = nullptr;
  const FrequencyCalibration* s2 = nullptr;
  // 5. Signal geometry.
  Eigen::Vector3d apc = Eigen::Vector3d::Zero();  // rotated for the Earth rotation during the flight
  double rho_m = 0.0;
  Eigen::Vector3d los = Eigen::Vector3d::Zero();  // receiver -> satellite
  double elevation_rad = 0.0;
  double azimuth_rad = 0.0;
  // 6. Antenna phase-centre variations (IF).
  double pcv_receiver_m = 0.0;
  double pcv_satellite_m = 0.0;
  double nadir_rad = 0.0;
  // 7. Troposphere mapping.
  MappingFunctions mf;
  // 8. Wind-up.
  double windup_cycles = 0.0;

  void reject(EpochMeasurements& out, RejectionReason reason, std::string why) const {
    out.rejected.push_back({o.satellite, reason, std::move(why)});
  }
};

namespace {

/// Throws when the caller's observed IF are not one per observation.
void checkObservedSize(const char* function, std::size_t observations, std::size_t observed) {
  if (observed == observations) return;
  throw std::invalid_argument(std::string("PppMeasurementModel::") + function + ": " + std::to_string(observed) +
                              " observed IF pairs for " + std::to_string(observations) + " observations");
}

}  // namespace

void PppMeasurementModel::evaluate(const std::vector<DualFrequencyObservation>& observations,
                                   const std::vector<ArcId>& arcs, const ReceiverState& state, WindupTracker* windup,
                                   EpochMeasurements& out, std::vector<ModelTerms>* terms) const {
  evaluateEpoch(observations, nullptr, arcs, state, windup, out, terms);
}

void PppMeasurementModel::evaluate(const std::vector<DualFrequencyObservation>& observations,
                                   const std::vector<ObservedIonosphereFree>& observed,
                                   const std::vector<ArcId>& arcs, const ReceiverState& state, WindupTracker* windup,
                                   EpochMeasurements& out, std::vector<ModelTerms>* terms) const {
  checkObservedSize("evaluate", observations.size(), observed.size());
  evaluateEpoch(observations, &observed, arcs, state, windup, out, terms);
}

void PppMeasurementModel::evaluateEpoch(const std::vector<DualFrequencyObservation>& observations,
                                        const std::vector<ObservedIonosphereFree>* observed,
                                        const std::vector<ArcId>& arcs, const ReceiverState& state,
                                        WindupTracker* windup, EpochMeasurements& out,
                                        std::vector<ModelTerms>* terms) const {
  out.used.clear();
  out.rejected.clear();
  if (terms != nullptr) terms->clear();
  if (observations.empty()) return;
  const GnssTime t_rx = observations.front().time;
  out.time = t_rx;
  const Eigen::Vector3d marker = state.position_ecef_m;
  if (!marker.allFinite() || marker.norm() < 1.0e6) {
    for (const auto& o : observations) out.rejected.push_back({o.satellite, RejectionReason::LinearisationPointUnusable, "linearisation point not usable"});
    return;
  }
  const bool arcs_ok = arcs.size() == observations.size();

  // 1. Per-epoch terms: local frame, Sun/Moon, station displacements, troposphere constants
  //    (those of the last call again when it was at the same point and time).
  if (!last_epoch_terms_ || !(last_epoch_terms_->t_rx == t_rx) || last_epoch_terms_->marker != marker)
    last_epoch_terms_ = std::make_shared<const EpochTerms>(epochTerms(marker, t_rx));
  const EpochTerms& epoch = *last_epoch_terms_;

  std::array<SystemTerms, kNumGnssSystems> systems;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const DualFrequencyObservation& o = observations[i];
    // 2. The system's terms: IF coefficients, receiver antenna phase centre.
    const SystemTerms& st = systemTerms(o, epoch, systems[static_cast<int>(o.satellite.system)]);
    SatelliteEvaluation sv(o, st, arcs_ok ? arcs[i] : 0, observed ? (*observed)[i] : observedIonosphereFree(o));
    // 3. The observed IF code and phase (and the receiver clock of the system).
    // 4. The satellite at emission: clock, orbit, eclipse, attitude, antenna phase centre.
    // 5. Signal geometry: Earth rotation during the flight, elevation and azimuth, cutoff.
    // 6. Receiver and satellite antenna phase-centre variations.
    // 7. Troposphere mapping.
    // 8. Phase wind-up.
    if (!observedCombinations(sv, epoch, state, out) || !satelliteAtEmission(sv, epoch, out) ||
        !signalGeometry(sv, epoch, out) || !phaseCentreVariations(sv, out)) {
      continue;
    }
    troposphereMapping(sv, epoch);
    if (!phaseWindup(sv, epoch, windup, out)) continue;
    // 9. The predicted observables, Jacobian and sigmas (and the model terms).
    addMeasurement(sv, epoch, state, windup, out, terms);
  }
}

// Step 1
PppMeasurementModel::EpochTerms PppMeasurementModel::epochTerms(const Eigen::Vector3d& marker,
                                                                const GnssTime& t_rx) const {
  EpochTerms e;
  e.t_rx = t_rx;
  e.marker = marker;
  e.geo = ecefToGeodetic(marker);
  e.enu_from_ecef = rotationEnuFromEcef(e.geo.latitude_rad, e.geo.longitude_rad);
  e.ecef_from_enu = e.enu_from_ecef.transpose();
  e.sun_moon = sunMoonPositionsEcef(t_rx);
  if (options_.solid_earth_tide) {
    e.station_offset += solidEarthTideDisplacementEcef_m(marker, e.sun_moon.sun_ecef_m, e.sun_moon.moon_ecef_m);
  }
  if (options_.ocean_loading && ocean_loading_) {
    e.station_offset += e.ecef_from_enu * oceanLoadingDisplacementEnu_m(*ocean_loading_, t_rx);
  }
  const Eigen::Vector3d& hen = receiver_antenna_.delta_hen_m;
  e.station_offset += e.ecef_from_enu * Eigen::Vector3d(hen.y(), hen.z(), hen.x());
  e.receiver_axes = northWestAntennaAxes(e.geo.latitude_rad, e.geo.longitude_rad);
  e.meteo = standardAtmosphere(e.geo.height_m);
  e.hopfield_zenith = modifiedHopfieldZenithDelays(e.meteo, e.geo.height_m);
  const auto zenithDry_m = [&](double height_m) {
    const SurfaceMeteo m = standardAtmosphere(height_m);
    return options_.dry_troposphere == DryTroposphereModel::ModifiedHopfield
               ? modifiedHopfieldZenithDelays(m, height_m).hydrostatic_m
               : saastamoinenZenithHydrostaticDelay_m(m.pressure_hpa, e.geo.latitude_rad, height_m);
  };
  e.zhd_m = zenithDry_m(e.geo.height_m);
  // The a-priori dry delay depends on the receiver height (standard atmosphere):
  // d ZHD / d h (~ -3e-4 m/m), so that the Jacobian holds m_d dZHD/dh along "up".
  e.zhd_rate = zenithDry_m(e.geo.height_m + 0.5) - zenithDry_m(e.geo.height_m - 0.5);
  if (options_.zwd_at_ellipsoid) {
    e.wet_height_ratio = standardWetDelayHeightRatio(e.geo.height_m);
    e.wet_height_log_rate_per_m = (standardWetDelayHeightRatio(e.geo.height_m + 0.5) -
                                   standardWetDelayHeightRatio(e.geo.height_m - 0.5)) / e.wet_height_ratio;
  }
  e.up_ecef = e.ecef_from_enu.col(2);
  e.day_of_year = t_rx.dayOfYear() + std::fmod(t_rx.mjd(), 1.0);
  e.mjd = t_rx.mjd();
  return e;
}

// Step 2
const PppMeasurementModel::SystemTerms& PppMeasurementModel::systemTerms(const DualFrequencyObservation& o,
                                                                         const EpochTerms& epoch,
                                                                         SystemTerms& st) const {
  if (st.done && st.band1 == o.code1.band && st.band2 == o.code2.band && st.frequency1_hz == o.frequency1_hz &&
      st.frequency2_hz == o.frequency2_hz)
    return st;
  const GnssSystem system = o.satellite.system;
  st = SystemTerms{};
  st.done = true;
  st.band1 = o.code1.band;
  st.band2 = o.code2.band;
  st.frequency1_hz = o.frequency1_hz;
  st.frequency2_hz = o.frequency2_hz;
  st.k = ionosphereFreeCoefficients(o.frequency1_hz, o.frequency2_hz);
  st.windup_wavelength_m = kSpeedOfLight_mps / (o.frequency1_hz + o.frequency2_hz);
  st.sigma_factor = options_.scale_sigma_for_ionosphere_free ? ionosphereFreeNoiseFactor(st.k) : 1.0;
  st.receiver_apc_ecef = epoch.station_offset;
  st.ok = true;
  if (options_.receiver_antenna == ReceiverAntennaPolicy::Off) return st;
  const bool required = options_.receiver_antenna == ReceiverAntennaPolicy::Required;
  if (receiver_calibration_ == nullptr) {
    st.ok = !required;  // Warn: reported once at construction
    st.missing = "missing receiver antenna calibration (" + receiver_source_ + ")";
    return st;
  }
  const ReceiverFrequencyLookup r1 = receiverFrequencyCalibration(
      *receiver_calibration_, system, antexFrequency(st.band1), options_.receiver_frequency_substitution);
  const ReceiverFrequencyLookup r2 = receiverFrequencyCalibration(
      *receiver_calibration_, system, antexFrequency(st.band2), options_.receiver_frequency_substitution);
  st.r1 = r1.calibration;
  st.r2 = r2.calibration;
  if (st.r1 != nullptr && st.r2 != nullptr && (r1.substituted || r2.substituted)) {
    warnReceiverAntenna(receiverSubstitutionNote(*receiver_calibration_, system, antexFrequency(st.band1), r1,
                                                 antexFrequency(st.band2), r2));
  }
  if (st.r1 == nullptr || st.r2 == nullptr) {
    st.ok = !required;
    st.missing = "missing receiver antenna calibration for " + receiver_calibration_->label() + " " +
                 systemLetter(system) + "0" + st.band1 + "/" + systemLetter(system) + "0" + st.band2;
    if (!required) warnReceiverAntenna(st.missing + ": receiver PCO/PCV not applied for these signals");
    st.r1 = st.r2 = nullptr;
  } else {
    const Eigen::Vector3d pco_neu = ionosphereFreeOffset(st.r1->pco_m, st.r2->pco_m, st.k);
    st.receiver_apc_ecef += epoch.ecef_from_enu * Eigen::Vector3d(pco_neu.y(), pco_neu.x(), pco_neu.z());
  }
  return st;
}

// Step 3
bool PppMeasurementModel::observedCombinations(SatelliteEvaluation& sv, const EpochTerms& epoch,
                                               const ReceiverState& state, EpochMeasurements& out) const {
  const DualFrequencyObservation& o = sv.o;
  const SystemTerms& st = sv.st;
  if (!st.ok) {
    sv.reject(out, RejectionReason::MissingAntennaCalibration, st.missing);
    return false;
  }
  sv.receiver_clock = state.layout.clock(o.satellite.system);
  if (sv.receiver_clock < 0) {
    sv.reject(out, RejectionReason::NoReceiverClock,
              std::string("no receiver clock for system ") + systemLetter(o.satellite.system) + " in the state layout");
    return false;
  }
  sv.receiver_apc = epoch.marker + st.receiver_apc_ecef;
  if (!std::isfinite(sv.code_if_m) || !std::isfinite(sv.phase_if_m) || sv.code_if_m < 1.0e7 || sv.code_if_m > 1.0e8) {
    sv.reject(out, RejectionReason::ObservationUnusable, format("observed IF code %.3f m / phase not usable", sv.code_if_m));
    return false;
  }
  return true;
}

// Step 4: clock and position at the emission time (GPST), eclipse, nominal
// attitude and the satellite antenna offset (IF, body frame; satellite_reference_point.h).
bool PppMeasurementModel::satelliteAtEmission(SatelliteEvaluation& sv, const EpochTerms& epoch,
                                              EpochMeasurements& out) const {
  const SatelliteId sat = sv.o.satellite;
  const std::optional<EmissionEphemeris> emission = emissionEphemeris(
      sat, epoch.t_rx, sv.code_if_m,
      [&](RejectionReason reason, std::string why) { sv.reject(out, reason, std::move(why)); });
  if (!emission) return false;
  sv.clock = emission->clock;
  sv.orbit = emission->orbit;
  // An antenna-phase-centre orbit: the position stands for both (the offset,
  // or with an L1 orbit all but the IF - L1 difference, is in it).
  const Eigen::Vector3d& com_tx = sv.orbit.position_ecef_m;
  const EphemerisReference orbit_reference = sv.orbit.reference;
  const bool orbit_at_apc = orbit_reference != EphemerisReference::CentreOfMass;
  if (options_.exclude_eclipse && eclipseState(com_tx, epoch.sun_moon.sun_ecef_m) != EclipseState::Sunlit) {
    sv.reject(out, RejectionReason::Eclipse, "satellite in the Earth's shadow (eclipse)");
    return false;
  }
  if (!satelliteAttitude(sv, epoch, out)) return false;
  sv.apc_tx = com_tx;
  if (!options_.satellite_antenna) return true;
  const AntennaCalibration* cal = satelliteCalibration(sat, epoch.t_rx);
  if (cal != nullptr) {
    sv.s1 = cal->frequency(sat.system, antexFrequency(sv.o.phase1.band));
    sv.s2 = cal->frequency(sat.system, antexFrequency(sv.o.phase2.band));
  }
  // An antenna-phase-centre orbit needs no offset: without a calibration it
  // goes on without satellite PCV (e.g. Galileo with a GPS-only ANTEX file).
  if ((sv.s1 == nullptr || sv.s2 == nullptr) && !orbit_at_apc) {
    sv.reject(out, RejectionReason::MissingAntennaCalibration,
              cal == nullptr ? "missing satellite antenna calibration (no ANTEX block valid at the epoch)"
                             : "missing satellite antenna calibration for frequencies of " + cal->label());
    return false;
  }
  const std::optional<Eigen::Vector3d> pco = ionosphereFreePhaseCentreOffset_m(
      orbit_reference, cal, sat.system, sv.o.phase1.band, sv.o.phase2.band, sv.st.k);
  if (pco) {
    if (orbit_reference != EphemerisReference::AntennaPhaseCentre) {
      sv.reference_offset_ecef = pco->x() * sv.axes.x_ecef + pco->y() * sv.axes.y_ecef + pco->z() * sv.axes.z_ecef;
      sv.apc_tx += sv.reference_offset_ecef;
    }
  } else {
    // Only an L1 orbit gets here (a centre-of-mass one without calibration was rejected).
    ++l1_reference_without_calibration_[static_cast<std::size_t>(sat.index())];
  }
  return true;
}

std::string_view yawManoeuvreHandlingName(YawManoeuvreHandling handling) {
  switch (handling) {
    case YawManoeuvreHandling::Model: return "model";
    case YawManoeuvreHandling::Exclude: return "exclude";
    case YawManoeuvreHandling::Nominal: return "nominal";
  }
  return "model";
}

// Step 4b: the body axes: nominal yaw steering, or in a noon/midnight turn the
// rate-limited yaw of the system's model, or the satellite left out (yaw_manoeuvre.h).
bool PppMeasurementModel::satelliteAttitude(SatelliteEvaluation& sv, const EpochTerms& epoch,
                                            EpochMeasurements& out) const {
  const Eigen::Vector3d& r = sv.orbit.position_ecef_m;
  const Eigen::Vector3d& v = sv.orbit.velocity_ecef_mps;
  const Eigen::Vector3d& sun = epoch.sun_moon.sun_ecef_m;
  sv.axes = nominalSatelliteAxes(r, v, sun);
  if (options_.yaw_manoeuvre == YawManoeuvreHandling::Nominal) return true;
  const std::optional<YawManoeuvreLimits> limits = yawManoeuvreLimits(sv.o.satellite.system);
  if (!limits) return true;
  const OrbitSunAngles angles = orbitSunAngles(r, v, sun);
  const double orbit_rate_radps = orbitAngularRate_radps(r, v);
  if (!inYawManoeuvre(angles, orbit_rate_radps, *limits)) return true;
  if (options_.yaw_manoeuvre == YawManoeuvreHandling::Model && limits->max_yaw_rate_radps > 0.0) {
    if (const std::optional<double> yaw_rad = rateLimitedYaw_rad(angles, orbit_rate_radps, *limits))
      sv.axes = satelliteAxesFromYaw(r, v, *yaw_rad);
    return true;
  }
  sv.reject(out, RejectionReason::YawManoeuvre, "satellite in a noon or midnight yaw turn (attitude not modelled)");
  return false;
}

// Step 5: Earth rotation during the flight (Sagnac): rotate by omega_e tau, tau =
// rho / c; elevation / azimuth at the marker's local frame.
bool PppMeasurementModel::signalGeometry(SatelliteEvaluation& sv, const EpochTerms& epoch,
                                         EpochMeasurements& out) const {
  double tau = (sv.apc_tx - sv.receiver_apc).norm() / kSpeedOfLight_mps;
  sv.apc = sv.apc_tx;
  for (int it = 0; it < 3; ++it) {
    sv.apc = rotateForEarthRotation(sv.apc_tx, tau);
    tau = (sv.apc - sv.receiver_apc).norm() / kSpeedOfLight_mps;
  }
  const Eigen::Vector3d diff = sv.apc - sv.receiver_apc;
  sv.rho_m = diff.norm();
  sv.los = diff / sv.rho_m;
  const Eigen::Vector3d los_enu = epoch.enu_from_ecef * sv.los;
  sv.elevation_rad = std::asin(std::clamp(los_enu.z(), -1.0, 1.0));
  sv.azimuth_rad = std::atan2(los_enu.x(), los_enu.y());
  if (sv.azimuth_rad < 0.0) sv.azimuth_rad += 2.0 * kPi;
  if (sv.elevation_rad < options_.elevation_cutoff_rad) {
    sv.reject(out, RejectionReason::BelowElevationCutoff,
              format("elevation %.1f deg below cutoff %.1f deg", sv.elevation_rad * kRadToDeg,
                     options_.elevation_cutoff_rad * kRadToDeg));
    return false;
  }
  return true;
}

// Step 6
bool PppMeasurementModel::phaseCentreVariations(SatelliteEvaluation& sv, EpochMeasurements& out) const {
  const SystemTerms& st = sv.st;
  if (st.r1 != nullptr && st.r2 != nullptr) {
    const double zenith = 0.5 * kPi - sv.elevation_rad;
    const auto v = combine(st.r1->pcv_m(zenith, sv.azimuth_rad), st.r2->pcv_m(zenith, sv.azimuth_rad), st.k);
    if (!v) {
      sv.reject(out, RejectionReason::UndefinedPhaseCentreVariation,
                format("receiver PCV undefined at zenith %.1f deg", zenith * kRadToDeg));
      return false;
    }
    sv.pcv_receiver_m = *v;
  }
  if (options_.satellite_antenna) sv.nadir_rad = std::acos(std::clamp(-sv.los.dot(sv.axes.z_ecef), -1.0, 1.0));
  if (options_.satellite_antenna && sv.s1 != nullptr && sv.s2 != nullptr) {
    const auto v = combine(sv.s1->pcv.evaluateNoAzimuth_m(sv.nadir_rad), sv.s2->pcv.evaluateNoAzimuth_m(sv.nadir_rad),
                           st.k);
    if (!v) {
      sv.reject(out, RejectionReason::UndefinedPhaseCentreVariation,
                format("satellite PCV undefined at nadir %.2f deg", sv.nadir_rad * kRadToDeg));
      return false;
    }
    sv.pcv_satellite_m = *v;
  }
  return true;
}

// Step 7
void PppMeasurementModel::troposphereMapping(SatelliteEvaluation& sv, const EpochTerms& epoch) const {
  const double elevation_rad = sv.elevation_rad;
  MappingFunctions& mf = sv.mf;
  if (options_.mapping == TroposphereMapping::ModifiedHopfield) {
    const TroposphereDelays slant = modifiedHopfieldSlantDelays(epoch.meteo, elevation_rad, epoch.geo.height_m);
    mf.hydrostatic = slant.hydrostatic_m / epoch.hopfield_zenith.hydrostatic_m;
    mf.wet = slant.wet_m / epoch.hopfield_zenith.wet_m;
  } else if (options_.mapping == TroposphereMapping::Niell) {
    mf = niellMapping(elevation_rad, epoch.geo.latitude_rad, epoch.geo.height_m, epoch.day_of_year);
  } else {
    mf = globalMappingFunction(elevation_rad, epoch.geo.latitude_rad, epoch.geo.longitude_rad, epoch.geo.height_m,
                               epoch.mjd);
  }
  if (options_.zwd_at_ellipsoid) mf.wet *= epoch.wet_height_ratio;  // the state is the ZWD at height 0
}

// Step 8
bool PppMeasurementModel::phaseWindup(SatelliteEvaluation& sv, const EpochTerms& epoch, const WindupTracker* windup,
                                      EpochMeasurements& out) const {
  if (!options_.phase_windup) return true;
  const std::optional<double> prev = windup != nullptr ? windup->previous(sv.o.satellite, sv.arc) : std::nullopt;
  const auto w = phaseWindup_cycles(sv.axes, epoch.receiver_axes, sv.apc, sv.receiver_apc, prev);
  if (!w) {
    sv.reject(out, RejectionReason::UndefinedWindup, "phase wind-up undefined (degenerate geometry)");
    return false;
  }
  sv.windup_cycles = *w;
  return true;
}

// Step 9: clocks and relativity, the predicted observables, Jacobian and sigmas.
void PppMeasurementModel::addMeasurement(const SatelliteEvaluation& sv, const EpochTerms& epoch,
                                         const ReceiverState& state, WindupTracker* windup, EpochMeasurements& out,
                                         std::vector<ModelTerms>* terms) const {
  const SatelliteId sat = sv.o.satellite;
  const SystemTerms& st = sv.st;
  const MappingFunctions& mf = sv.mf;
  const double dts = sv.clock.clock_bias_s;
  const double rel_s = relativisticClockCorrection_s(sv.orbit.position_ecef_m, sv.orbit.velocity_ecef_mps);
  const double shapiro = options_.shapiro ? shapiroDelay_m(sv.apc, sv.receiver_apc) : 0.0;
  const GradientPartials gradient = state.layout.hasGradients()
                                       ? gradientPartials(sv.elevation_rad, sv.azimuth_rad)
                                       : GradientPartials{};
  const double gradient_m = gradient.north * state.gradient_north_m + gradient.east * state.gradient_east_m;
  const double common = sv.rho_m + state.clock_m(sat.system) - kSpeedOfLight_mps * (dts + rel_s) +
                        mf.hydrostatic * epoch.zhd_m + mf.wet * state.zwd_m + shapiro + sv.pcv_receiver_m +
                        sv.pcv_satellite_m + gradient_m;
  SatelliteMeasurement m;
  m.satellite = sat;
  m.arc = sv.arc;
  m.predicted_code_m = common;
  m.predicted_phase_m = common + st.windup_wavelength_m * sv.windup_cycles;
  m.observed_code_m = sv.code_if_m;
  m.observed_phase_m = sv.phase_if_m;
  Eigen::Vector3d d_position = -sv.los + mf.hydrostatic * epoch.zhd_rate * epoch.up_ecef;
  if (options_.zwd_at_ellipsoid) d_position += mf.wet * state.zwd_m * epoch.wet_height_log_rate_per_m * epoch.up_ecef;
  m.jacobian = Eigen::RowVectorXd::Zero(state.layout.dim());
  m.jacobian.segment<ReceiverStateLayout::kPositionSize>(state.layout.position()) = d_position.transpose();
  m.jacobian(state.layout.zwd()) = mf.wet;
  m.jacobian(sv.receiver_clock) = 1.0;  // the satellite's own system clock
  if (state.layout.hasGradients()) {
    m.jacobian(state.layout.gradientNorth()) = gradient.north;
    m.jacobian(state.layout.gradientEast()) = gradient.east;
  }
  const double sin_el = std::max(std::sin(sv.elevation_rad), 1.0e-3);
  m.phase_sigma_m = options_.phase_sigma_zenith_m * st.sigma_factor / sin_el;
  m.code_sigma_m = m.phase_sigma_m * options_.code_phase_ratio * sv.o.code_sigma_factor;
  if (options_.ephemeris_sigmas) {
    const double orbit_sigma_m = sv.orbit.position_sigma_m.value_or(0.0);
    const double clock_sigma_m = sv.clock.clock_sigma_m.value_or(0.0);
    const double product_var_m2 = orbit_sigma_m * orbit_sigma_m + clock_sigma_m * clock_sigma_m;
    m.phase_sigma_m = std::sqrt(m.phase_sigma_m * m.phase_sigma_m + product_var_m2);
    m.code_sigma_m = std::sqrt(m.code_sigma_m * m.code_sigma_m + product_var_m2);
  }
  m.elevation_rad = sv.elevation_rad;
  m.azimuth_rad = sv.azimuth_rad;
  m.satellite_apc_ecef_m = sv.apc;
  m.receiver_apc_offset_ecef_m = st.receiver_apc_ecef;
  if (!std::isfinite(m.predicted_code_m) || !std::isfinite(m.predicted_phase_m) || !m.jacobian.allFinite()) {
    sv.reject(out, RejectionReason::NonFiniteModel, "non-finite model value");
    return;
  }
  if (windup != nullptr && options_.phase_windup) windup->update(sat, sv.arc, sv.windup_cycles);
  out.used.push_back(m);
  if (terms != nullptr) {
    terms->push_back(modelTerms(sv, epoch, shapiro, rel_s));
    terms->back().troposphere_gradient_m = gradient_m;
  }
}

ModelTerms PppMeasurementModel::modelTerms(const SatelliteEvaluation& sv, const EpochTerms& epoch, double shapiro_m,
                                           double relativistic_s) const {
  ModelTerms tm;
  tm.satellite = sv.o.satellite;
  tm.geometric_range_m = sv.rho_m;
  tm.satellite_clock_m = -kSpeedOfLight_mps * sv.clock.clock_bias_s;
  tm.relativistic_clock_m = -kSpeedOfLight_mps * relativistic_s;
  tm.troposphere_dry_m = sv.mf.hydrostatic * epoch.zhd_m;
  tm.wet_mapping = sv.mf.wet;
  tm.shapiro_m = shapiro_m;
  tm.receiver_pcv_m = sv.pcv_receiver_m;
  tm.satellite_pcv_m = sv.pcv_satellite_m;
  tm.windup_cycles = sv.windup_cycles;
  tm.windup_m = sv.st.windup_wavelength_m * sv.windup_cycles;
  tm.sagnac_m = sv.rho_m - (sv.apc_tx - sv.receiver_apc).norm();
  tm.nadir_rad = sv.nadir_rad;
  tm.satellite_apc_at_transmission_ecef_m = sv.apc_tx;
  tm.satellite_reference_offset_ecef_m = sv.reference_offset_ecef;
  tm.receiver_apc_ecef_m = sv.receiver_apc;
  return tm;
}

void PppMeasurementModel::evaluateStart(const std::vector<DualFrequencyObservation>& observations,
                                        const ReceiverState& state, EpochMeasurements& out) const {
  evaluateStartEpoch(observations, nullptr, state, out);
}

void PppMeasurementModel::evaluateStart(const std::vector<DualFrequencyObservation>& observations,
                                        const std::vector<ObservedIonosphereFree>& observed,
                                        const ReceiverState& state, EpochMeasurements& out) const {
  checkObservedSize("evaluateStart", observations.size(), observed.size());
  evaluateStartEpoch(observations, &observed, state, out);
}

void PppMeasurementModel::evaluateStartEpoch(const std::vector<DualFrequencyObservation>& observations,
                                             const std::vector<ObservedIonosphereFree>* observed,
                                             const ReceiverState& state, EpochMeasurements& out) const {
  out.used.clear();
  out.rejected.clear();
  if (observations.empty()) return;
  const GnssTime t_rx = observations.front().time;
  out.time = t_rx;
  const Eigen::Vector3d receiver = state.position_ecef_m;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const DualFrequencyObservation& o = observations[i];
    const SatelliteId sat = o.satellite;
    auto reject = [&](RejectionReason reason, std::string why) { out.rejected.push_back({sat, reason, std::move(why)}); };
    const int receiver_clock = state.layout.clock(sat.system);
    if (receiver_clock < 0) {
      reject(RejectionReason::NoReceiverClock,
             std::string("no receiver clock for system ") + systemLetter(sat.system) + " in the state layout");
      continue;
    }
    const auto [code_if, phase_if] = observed ? (*observed)[i] : observedIonosphereFree(o);
    if (!std::isfinite(code_if) || code_if < 1.0e7 || code_if > 1.0e8) {
      reject(RejectionReason::ObservationUnusable, format("observed IF code %.3f m not usable", code_if));
      continue;
    }
    const std::optional<EmissionEphemeris> emission = emissionEphemeris(sat, t_rx, code_if, reject);
    if (!emission) continue;
    const double dts = emission->clock.clock_bias_s;
    const Eigen::Vector3d& sat_tx = emission->orbit.position_ecef_m;
    double tau = (sat_tx - receiver).norm() / kSpeedOfLight_mps;
    Eigen::Vector3d sat_rx = sat_tx;
    for (int it = 0; it < 3; ++it) {
      sat_rx = rotateForEarthRotation(sat_tx, tau);
      tau = (sat_rx - receiver).norm() / kSpeedOfLight_mps;
    }
    const Eigen::Vector3d diff = sat_rx - receiver;
    const double rho = diff.norm();
    const Eigen::Vector3d los = diff / rho;
    const double rel_s = relativisticClockCorrection_s(sat_tx, emission->orbit.velocity_ecef_mps);
    SatelliteMeasurement m;
    m.satellite = sat;
    m.predicted_code_m = rho + state.clock_m(sat.system) - kSpeedOfLight_mps * (dts + rel_s);
    m.predicted_phase_m = m.predicted_code_m;
    m.observed_code_m = code_if;
    m.observed_phase_m = phase_if;
    m.jacobian = Eigen::RowVectorXd::Zero(state.layout.dim());
    m.jacobian.segment<ReceiverStateLayout::kPositionSize>(state.layout.position()) = -los.transpose();
    m.jacobian(receiver_clock) = 1.0;
    const IonosphereFreeCoefficients k = ionosphereFreeCoefficients(o.frequency1_hz, o.frequency2_hz);
    const double sigma_factor = options_.scale_sigma_for_ionosphere_free ? ionosphereFreeNoiseFactor(k) : 1.0;
    m.phase_sigma_m = options_.phase_sigma_zenith_m * sigma_factor;
    m.code_sigma_m = m.phase_sigma_m * options_.code_phase_ratio * o.code_sigma_factor;
    m.satellite_apc_ecef_m = sat_rx;
    if (!std::isfinite(m.predicted_code_m) || !m.jacobian.allFinite()) {
      reject(RejectionReason::NonFiniteModel, "non-finite model value");
      continue;
    }
    out.used.push_back(m);
  }
}

}  // namespace ppp
