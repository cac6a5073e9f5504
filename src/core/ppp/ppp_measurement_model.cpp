#include "ppp_bayes_tree/ppp/ppp_measurement_model.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "ppp_bayes_tree/models/ionosphere_free.h"
#include "ppp_bayes_tree/models/ocean_loading.h"
#include "ppp_bayes_tree/models/phase_windup.h"
#include "ppp_bayes_tree/models/relativity.h"
#include "ppp_bayes_tree/models/satellite_attitude.h"
#include "ppp_bayes_tree/models/satellite_eclipse.h"
#include "ppp_bayes_tree/models/satellite_reference_point.h"
#include "ppp_bayes_tree/models/signal_geometry.h"
#include "ppp_bayes_tree/models/solid_earth_tide.h"
#include "ppp_bayes_tree/models/sun_moon_position.h"
#include "ppp_bayes_tree/models/troposphere.h"
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
struct EmissionEphemeris {
  EphemerisClock clock;
  EphemerisOrbit orbit;
};

template <typename Reject>
std::optional<EmissionEphemeris> ephemerisAtEmission(const EphemerisSource& ephemeris, const SatelliteId& sat,
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
  return EmissionEphemeris{*clock.value, *orbit.value};
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

void PppMeasurementModel::evaluate(const std::vector<DualFrequencyObservation>& observations,
                                   const std::vector<ArcId>& arcs, const ReceiverState& state, WindupTracker* windup,
                                   EpochMeasurements& out, std::vector<ModelTerms>* terms) const {
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

  // ---- per-epoch terms: local frame, Sun/Moon, station displacements, troposphere constants.
  const Geodetic geo = ecefToGeodetic(marker);
  const Eigen::Matrix3d enu_from_ecef = rotationEnuFromEcef(geo.latitude_rad, geo.longitude_rad);
  const Eigen::Matrix3d ecef_from_enu = enu_from_ecef.transpose();
  const SunMoonPositions sun_moon = sunMoonPositionsEcef(t_rx);
  Eigen::Vector3d station_offset = Eigen::Vector3d::Zero();  // marker -> ARP, ECEF
  if (options_.solid_earth_tide) {
    station_offset += solidEarthTideDisplacementEcef_m(marker, sun_moon.sun_ecef_m, sun_moon.moon_ecef_m);
  }
  if (options_.ocean_loading && ocean_loading_) {
    station_offset += ecef_from_enu * oceanLoadingDisplacementEnu_m(*ocean_loading_, t_rx);
  }
  const Eigen::Vector3d& hen = receiver_antenna_.delta_hen_m;
  station_offset += ecef_from_enu * Eigen::Vector3d(hen.y(), hen.z(), hen.x());
  const ReceiverAntennaAxes receiver_axes = northWestAntennaAxes(geo.latitude_rad, geo.longitude_rad);
  const SurfaceMeteo meteo = standardAtmosphere(geo.height_m);
  const TroposphereDelays hopfield_zenith = modifiedHopfieldZenithDelays(meteo, geo.height_m);
  const auto zenithDry_m = [&](double height_m) {
    const SurfaceMeteo m = standardAtmosphere(height_m);
    return options_.dry_troposphere == DryTroposphereModel::ModifiedHopfield
               ? modifiedHopfieldZenithDelays(m, height_m).hydrostatic_m
               : saastamoinenZenithHydrostaticDelay_m(m.pressure_hpa, geo.latitude_rad, height_m);
  };
  const double zhd_m = zenithDry_m(geo.height_m);
  // The a-priori dry delay depends on the receiver height (standard atmosphere):
  // d ZHD / d h (~ -3e-4 m/m), so that the Jacobian holds m_d dZHD/dh along "up".
  const double zhd_rate = zenithDry_m(geo.height_m + 0.5) - zenithDry_m(geo.height_m - 0.5);
  const Eigen::Vector3d up_ecef = ecef_from_enu.col(2);
  const double day_of_year = t_rx.dayOfYear() + std::fmod(t_rx.mjd(), 1.0);
  const double mjd = t_rx.mjd();

  // Per-system receiver PCO (IF, ECEF) for the frequency pair: computed on first use.
  struct SystemTerms {
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
  };
  std::array<SystemTerms, kNumGnssSystems> systems;

  for (std::size_t i = 0; i < observations.size(); ++i) {
    const DualFrequencyObservation& o = observations[i];
    const SatelliteId sat = o.satellite;
    auto reject = [&](RejectionReason reason, std::string why) { out.rejected.push_back({sat, reason, std::move(why)}); };
    SystemTerms& st = systems[static_cast<int>(sat.system)];
    if (!st.done || st.band1 != o.code1.band || st.band2 != o.code2.band) {
      st = SystemTerms{};
      st.done = true;
      st.band1 = o.code1.band;
      st.band2 = o.code2.band;
      st.k = ionosphereFreeCoefficients(o.frequency1_hz, o.frequency2_hz);
      st.windup_wavelength_m = kSpeedOfLight_mps / (o.frequency1_hz + o.frequency2_hz);
      st.sigma_factor = options_.scale_sigma_for_ionosphere_free ? ionosphereFreeNoiseFactor(st.k) : 1.0;
      st.receiver_apc_ecef = station_offset;
      st.ok = true;
      if (options_.receiver_antenna != ReceiverAntennaPolicy::Off) {
        const bool required = options_.receiver_antenna == ReceiverAntennaPolicy::Required;
        if (receiver_calibration_ == nullptr) {
          st.ok = !required;  // Warn: reported once at construction
          st.missing = "missing receiver antenna calibration (" + receiver_source_ + ")";
        } else {
          const ReceiverFrequencyLookup r1 = receiverFrequencyCalibration(
              *receiver_calibration_, sat.system, antexFrequency(st.band1), options_.receiver_frequency_substitution);
          const ReceiverFrequencyLookup r2 = receiverFrequencyCalibration(
              *receiver_calibration_, sat.system, antexFrequency(st.band2), options_.receiver_frequency_substitution);
          st.r1 = r1.calibration;
          st.r2 = r2.calibration;
          if (st.r1 != nullptr && st.r2 != nullptr && (r1.substituted || r2.substituted)) {
            warnReceiverAntenna(receiverSubstitutionNote(*receiver_calibration_, sat.system, antexFrequency(st.band1),
                                                         r1, antexFrequency(st.band2), r2));
          }
          if (st.r1 == nullptr || st.r2 == nullptr) {
            st.ok = !required;
            st.missing = "missing receiver antenna calibration for " + receiver_calibration_->label() + " " +
                         systemLetter(sat.system) + "0" + st.band1 + "/" + systemLetter(sat.system) + "0" + st.band2;
            if (!required) warnReceiverAntenna(st.missing + ": receiver PCO/PCV not applied for these signals");
            st.r1 = st.r2 = nullptr;
          } else {
            const Eigen::Vector3d pco_neu = ionosphereFreeOffset(st.r1->pco_m, st.r2->pco_m, st.k);
            st.receiver_apc_ecef += ecef_from_enu * Eigen::Vector3d(pco_neu.y(), pco_neu.x(), pco_neu.z());
          }
        }
      }
    }
    if (!st.ok) {
      reject(RejectionReason::MissingAntennaCalibration, st.missing);
      continue;
    }
    const int receiver_clock = state.layout.clock(sat.system);
    if (receiver_clock < 0) {
      reject(RejectionReason::NoReceiverClock,
             std::string("no receiver clock for system ") + systemLetter(sat.system) + " in the state layout");
      continue;
    }
    const Eigen::Vector3d receiver_apc = marker + st.receiver_apc_ecef;
    const double code_if = ionosphereFree(o.code1_m, o.code2_m, st.k);
    const double phase_if = ionosphereFree(o.phase1_cycles * kSpeedOfLight_mps / o.frequency1_hz,
                                           o.phase2_cycles * kSpeedOfLight_mps / o.frequency2_hz, st.k);
    if (!std::isfinite(code_if) || !std::isfinite(phase_if) || code_if < 1.0e7 || code_if > 1.0e8) {
      reject(RejectionReason::ObservationUnusable, format("observed IF code %.3f m / phase not usable", code_if));
      continue;
    }

    // ---- satellite clock and position at the emission time (GPST).
    const std::optional<EmissionEphemeris> emission = ephemerisAtEmission(ephemeris_, sat, t_rx, code_if, reject);
    if (!emission) continue;
    const double dts = emission->clock.clock_bias_s;
    // An antenna-phase-centre orbit: the position stands for both (the offset,
    // or with an L1 orbit all but the IF - L1 difference, is in it).
    const Eigen::Vector3d& com_tx = emission->orbit.position_ecef_m;
    const Eigen::Vector3d& vel_tx = emission->orbit.velocity_ecef_mps;
    const EphemerisReference orbit_reference = emission->orbit.reference;
    const bool orbit_at_apc = orbit_reference != EphemerisReference::CentreOfMass;
    if (options_.exclude_eclipse && eclipseState(com_tx, sun_moon.sun_ecef_m) != EclipseState::Sunlit) {
      reject(RejectionReason::Eclipse, "satellite in the Earth's shadow (eclipse)");
      continue;
    }
    const SatelliteBodyAxes axes = nominalSatelliteAxes(com_tx, vel_tx, sun_moon.sun_ecef_m);

    // ---- satellite antenna offset (IF, body frame; satellite_reference_point.h).
    Eigen::Vector3d apc_tx = com_tx;
    const FrequencyCalibration* s1 = nullptr;
    const FrequencyCalibration* s2 = nullptr;
    Eigen::Vector3d reference_offset_ecef = Eigen::Vector3d::Zero();
    if (options_.satellite_antenna) {
      const AntennaCalibration* cal = satelliteCalibration(sat, t_rx);
      if (cal != nullptr) {
        s1 = cal->frequency(sat.system, antexFrequency(o.phase1.band));
        s2 = cal->frequency(sat.system, antexFrequency(o.phase2.band));
      }
      // An antenna-phase-centre orbit needs no offset: without a calibration it
      // goes on without satellite PCV (e.g. Galileo with a GPS-only ANTEX file).
      if ((s1 == nullptr || s2 == nullptr) && !orbit_at_apc) {
        reject(RejectionReason::MissingAntennaCalibration,
               cal == nullptr ? "missing satellite antenna calibration (no ANTEX block valid at the epoch)"
                              : "missing satellite antenna calibration for frequencies of " + cal->label());
        continue;
      }
      const std::optional<Eigen::Vector3d> pco =
          ionosphereFreePhaseCentreOffset_m(orbit_reference, cal, sat.system, o.phase1.band, o.phase2.band, st.k);
      if (pco) {
        if (orbit_reference != EphemerisReference::AntennaPhaseCentre) {
          reference_offset_ecef = pco->x() * axes.x_ecef + pco->y() * axes.y_ecef + pco->z() * axes.z_ecef;
          apc_tx += reference_offset_ecef;
        }
      } else {
        // Only an L1 orbit gets here (a centre-of-mass one without calibration was rejected).
        ++l1_reference_without_calibration_[static_cast<std::size_t>(sat.index())];
      }
    }

    // ---- Earth rotation during the flight (Sagnac): rotate by omega_e tau, tau = rho / c.
    double tau = (apc_tx - receiver_apc).norm() / kSpeedOfLight_mps;
    Eigen::Vector3d apc = apc_tx;
    for (int it = 0; it < 3; ++it) {
      apc = rotateForEarthRotation(apc_tx, tau);
      tau = (apc - receiver_apc).norm() / kSpeedOfLight_mps;
    }
    const Eigen::Vector3d diff = apc - receiver_apc;
    const double rho = diff.norm();
    const Eigen::Vector3d los = diff / rho;  // receiver -> satellite

    // ---- elevation / azimuth at the marker's local frame.
    const Eigen::Vector3d los_enu = enu_from_ecef * los;
    const double elevation = std::asin(std::clamp(los_enu.z(), -1.0, 1.0));
    double azimuth = std::atan2(los_enu.x(), los_enu.y());
    if (azimuth < 0.0) azimuth += 2.0 * kPi;
    if (elevation < options_.elevation_cutoff_rad) {
      reject(RejectionReason::BelowElevationCutoff, format("elevation %.1f deg below cutoff %.1f deg", elevation * kRadToDeg,
                    options_.elevation_cutoff_rad * kRadToDeg));
      continue;
    }

    // ---- antenna phase-centre variations (IF).
    double pcv_r = 0.0, pcv_s = 0.0, nadir = 0.0;
    if (st.r1 != nullptr && st.r2 != nullptr) {
      const double zenith = 0.5 * kPi - elevation;
      const auto v = combine(st.r1->pcv_m(zenith, azimuth), st.r2->pcv_m(zenith, azimuth), st.k);
      if (!v) {
        reject(RejectionReason::UndefinedPhaseCentreVariation, format("receiver PCV undefined at zenith %.1f deg", zenith * kRadToDeg));
        continue;
      }
      pcv_r = *v;
    }
    if (options_.satellite_antenna) nadir = std::acos(std::clamp(-los.dot(axes.z_ecef), -1.0, 1.0));
    if (options_.satellite_antenna && s1 != nullptr && s2 != nullptr) {
      const auto v = combine(s1->pcv.evaluateNoAzimuth_m(nadir), s2->pcv.evaluateNoAzimuth_m(nadir), st.k);
      if (!v) {
        reject(RejectionReason::UndefinedPhaseCentreVariation, format("satellite PCV undefined at nadir %.2f deg", nadir * kRadToDeg));
        continue;
      }
      pcv_s = *v;
    }

    // ---- troposphere.
    MappingFunctions mf;
    if (options_.mapping == TroposphereMapping::ModifiedHopfield) {
      const TroposphereDelays slant = modifiedHopfieldSlantDelays(meteo, elevation, geo.height_m);
      mf.hydrostatic = slant.hydrostatic_m / hopfield_zenith.hydrostatic_m;
      mf.wet = slant.wet_m / hopfield_zenith.wet_m;
    } else if (options_.mapping == TroposphereMapping::Niell) {
      mf = niellMapping(elevation, geo.latitude_rad, geo.height_m, day_of_year);
    } else {
      mf = globalMappingFunction(elevation, geo.latitude_rad, geo.longitude_rad, geo.height_m, mjd);
    }

    // ---- clocks and relativity.
    const double rel_s = relativisticClockCorrection_s(com_tx, vel_tx);
    const double shapiro = options_.shapiro ? shapiroDelay_m(apc, receiver_apc) : 0.0;

    // ---- wind-up.
    double windup_cycles = 0.0;
    const ArcId arc = arcs_ok ? arcs[i] : 0;
    if (options_.phase_windup) {
      const std::optional<double> prev = windup != nullptr ? windup->previous(sat, arc) : std::nullopt;
      const auto w = phaseWindup_cycles(axes, receiver_axes, apc, receiver_apc, prev);
      if (!w) {
        reject(RejectionReason::UndefinedWindup, "phase wind-up undefined (degenerate geometry)");
        continue;
      }
      windup_cycles = *w;
    }

    const double common = rho + state.clock_m(sat.system) - kSpeedOfLight_mps * (dts + rel_s) + mf.hydrostatic * zhd_m +
                          mf.wet * state.zwd_m + shapiro + pcv_r + pcv_s;
    SatelliteMeasurement m;
    m.satellite = sat;
    m.arc = arc;
    m.predicted_code_m = common;
    m.predicted_phase_m = common + st.windup_wavelength_m * windup_cycles;
    m.observed_code_m = code_if;
    m.observed_phase_m = phase_if;
    const Eigen::Vector3d d_position = -los + mf.hydrostatic * zhd_rate * up_ecef;
    m.jacobian = Eigen::RowVectorXd::Zero(state.layout.dim());
    m.jacobian.segment<ReceiverStateLayout::kPositionSize>(state.layout.position()) = d_position.transpose();
    m.jacobian(state.layout.zwd()) = mf.wet;
    m.jacobian(receiver_clock) = 1.0;  // the satellite's own system clock
    const double sin_el = std::max(std::sin(elevation), 1.0e-3);
    m.phase_sigma_m = options_.phase_sigma_zenith_m * st.sigma_factor / sin_el;
    m.code_sigma_m = m.phase_sigma_m * options_.code_phase_ratio;
    if (options_.ephemeris_sigmas) {
      const double orbit_sigma_m = emission->orbit.position_sigma_m.value_or(0.0);
      const double clock_sigma_m = emission->clock.clock_sigma_m.value_or(0.0);
      const double product_var_m2 = orbit_sigma_m * orbit_sigma_m + clock_sigma_m * clock_sigma_m;
      m.phase_sigma_m = std::sqrt(m.phase_sigma_m * m.phase_sigma_m + product_var_m2);
      m.code_sigma_m = std::sqrt(m.code_sigma_m * m.code_sigma_m + product_var_m2);
    }
    m.elevation_rad = elevation;
    m.azimuth_rad = azimuth;
    m.satellite_apc_ecef_m = apc;
    m.receiver_apc_offset_ecef_m = st.receiver_apc_ecef;
    if (!std::isfinite(m.predicted_code_m) || !std::isfinite(m.predicted_phase_m) || !m.jacobian.allFinite()) {
      reject(RejectionReason::NonFiniteModel, "non-finite model value");
      continue;
    }
    if (windup != nullptr && options_.phase_windup) windup->update(sat, arc, windup_cycles);
    out.used.push_back(m);
    if (terms != nullptr) {
      ModelTerms tm;
      tm.satellite = sat;
      tm.geometric_range_m = rho;
      tm.satellite_clock_m = -kSpeedOfLight_mps * dts;
      tm.relativistic_clock_m = -kSpeedOfLight_mps * rel_s;
      tm.troposphere_dry_m = mf.hydrostatic * zhd_m;
      tm.wet_mapping = mf.wet;
      tm.shapiro_m = shapiro;
      tm.receiver_pcv_m = pcv_r;
      tm.satellite_pcv_m = pcv_s;
      tm.windup_cycles = windup_cycles;
      tm.windup_m = st.windup_wavelength_m * windup_cycles;
      tm.sagnac_m = rho - (apc_tx - receiver_apc).norm();
      tm.nadir_rad = nadir;
      tm.satellite_apc_at_transmission_ecef_m = apc_tx;
      tm.satellite_reference_offset_ecef_m = reference_offset_ecef;
      tm.receiver_apc_ecef_m = receiver_apc;
      terms->push_back(tm);
    }
  }
}

void PppMeasurementModel::evaluateStart(const std::vector<DualFrequencyObservation>& observations,
                                        const ReceiverState& state, EpochMeasurements& out) const {
  out.used.clear();
  out.rejected.clear();
  if (observations.empty()) return;
  const GnssTime t_rx = observations.front().time;
  out.time = t_rx;
  const Eigen::Vector3d receiver = state.position_ecef_m;
  for (const DualFrequencyObservation& o : observations) {
    const SatelliteId sat = o.satellite;
    auto reject = [&](RejectionReason reason, std::string why) { out.rejected.push_back({sat, reason, std::move(why)}); };
    const int receiver_clock = state.layout.clock(sat.system);
    if (receiver_clock < 0) {
      reject(RejectionReason::NoReceiverClock,
             std::string("no receiver clock for system ") + systemLetter(sat.system) + " in the state layout");
      continue;
    }
    const IonosphereFreeCoefficients k = ionosphereFreeCoefficients(o.frequency1_hz, o.frequency2_hz);
    const double code_if = ionosphereFree(o.code1_m, o.code2_m, k);
    const double phase_if = ionosphereFree(o.phase1_cycles * kSpeedOfLight_mps / o.frequency1_hz,
                                           o.phase2_cycles * kSpeedOfLight_mps / o.frequency2_hz, k);
    if (!std::isfinite(code_if) || code_if < 1.0e7 || code_if > 1.0e8) {
      reject(RejectionReason::ObservationUnusable, format("observed IF code %.3f m not usable", code_if));
      continue;
    }
    const std::optional<EmissionEphemeris> emission = ephemerisAtEmission(ephemeris_, sat, t_rx, code_if, reject);
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
    const double sigma_factor = options_.scale_sigma_for_ionosphere_free ? ionosphereFreeNoiseFactor(k) : 1.0;
    m.phase_sigma_m = options_.phase_sigma_zenith_m * sigma_factor;
    m.code_sigma_m = m.phase_sigma_m * options_.code_phase_ratio;
    m.satellite_apc_ecef_m = sat_rx;
    if (!std::isfinite(m.predicted_code_m) || !m.jacobian.allFinite()) {
      reject(RejectionReason::NonFiniteModel, "non-finite model value");
      continue;
    }
    out.used.push_back(m);
  }
}

}  // namespace ppp
