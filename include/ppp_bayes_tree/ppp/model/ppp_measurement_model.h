#pragma once
// PppMeasurementModel: the single ionosphere-free (IF) code and phase model of
// both estimators (the EKF's update and the smoother's factors). For one epoch
// and a linearisation point X = (marker position ECEF, ZWD, receiver clock c*dt
// of the satellite's system; receiver_state_layout.h) it gives per satellite the
// observed and predicted IF observables, the Jacobian row d(predicted)/dX, the
// elevation-dependent sigmas, or the reason why the satellite is rejected.
// Satellite orbits and clocks come from an EphemerisSource, antenna
// calibrations from an AntennaCalibrationProvider, the wind-up continuity from
// the caller's WindupTracker.
//
// The observation equations, the troposphere, the weighting, the satellite
// reference point and the receiver antenna policy: doc/measurement_model.md.
//
// References: Kouba J. (2009) A guide to using International GNSS Service (IGS)
// products; Teunissen P.J.G., Montenbruck O. (eds.) (2017) Springer Handbook of
// Global Navigation Satellite Systems, ch. 25; Boehm J. et al. (2006) Global
// Mapping Function (GMF), Geophys. Res. Lett. 33; Chen G., Herring T.A. (1997)
// J. Geophys. Res. 102(B9) (gradients); Wu J.T. et al. (1993) Manuscripta
// Geodaetica 18 (wind-up).
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <memory>

#include "ppp_bayes_tree/models/antenna_calibration_provider.h"
#include "ppp_bayes_tree/models/ephemeris_source.h"
#include "ppp_bayes_tree/models/receiver_frequency_substitution.h"
#include "ppp_bayes_tree/types/ocean_loading_coefficients.h"
#include "ppp_bayes_tree/ppp/model/dual_frequency_observation.h"
#include "ppp_bayes_tree/ppp/model/observed_ionosphere_free.h"
#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {

enum class DryTroposphereModel { ModifiedHopfield, Saastamoinen };
enum class TroposphereMapping {
  ModifiedHopfield,  // the method's default: slant/zenith ratio of the Hopfield integration
  Niell,
  Gmf,
};

/// The attitude of a satellite in a noon or midnight yaw turn (models/yaw_manoeuvre.h).
enum class YawManoeuvreHandling {
  Model,    // GPS: the rate-limited yaw (Kouba 2009); a system without a yaw model (Galileo) is rejected in its window
  Exclude,  // every satellite in its turn window is rejected
  Nominal,  // nominal yaw steering throughout (the simulator's attitude)
};
std::string_view yawManoeuvreHandlingName(YawManoeuvreHandling handling);  // model | exclude | nominal

/// What to do about the receiver antenna calibration (PCO + PCV).
enum class ReceiverAntennaPolicy {
  Required,  // a satellite without it is rejected ("missing receiver antenna calibration")
  Warn,      // go on without it when missing, reported once
  Off,       // never applied
};
std::string_view receiverAntennaPolicyName(ReceiverAntennaPolicy policy);

struct MeasurementModelOptions {
  double elevation_cutoff_rad = 7.0 * kDegToRad;
  /// Undifferenced phase sigma of one frequency at zenith [m] (RTKLIB stats-errphase).
  double phase_sigma_zenith_m = 0.003;
  /// Code sigma / phase sigma (RTKLIB stats-eratio1 is 100). 300 (IF code sigma
  /// 2.7 m at zenith for GPS): the IF code errors are not white; over an hour
  /// they hold constant per-satellite offsets of 0.2-0.7 m (ZIM2 postfit code
  /// means with CODE OSB and IGS clocks, ppp_solve residual statistics), which
  /// a white-noise weight of 0.9 m lets pull the float solution for tens of
  /// minutes (measured: doc/studies/config_defaults.md).
  double code_phase_ratio = 300.0;
  /// Multiply the sigmas by sqrt(alpha^2 + beta^2) for the IF combination.
  bool scale_sigma_for_ionosphere_free = true;
  /// Add the ephemeris source's orbit and clock sigmas (EphemerisOrbit::
  /// position_sigma_m, EphemerisClock::clock_sigma_m, when it gives them) to the
  /// code and phase variances: sigma^2 += orbit^2 + clock^2 (a range error
  /// common to code and phase). Broadcast records give the URA/SISA, the live
  /// input's broadcast fallback its widened sigmas (app/live_gnss_input.h);
  /// precise products and SSR give none. Default false (sigmas as configured).
  bool ephemeris_sigmas = false;
  DryTroposphereModel dry_troposphere = DryTroposphereModel::ModifiedHopfield;
  /// GMF (Boehm et al. 2006) by default: it fits real data better than the
  /// method's modified Hopfield ray integration (config/method_table.yaml;
  /// measured: doc/studies/config_defaults.md).
  TroposphereMapping mapping = TroposphereMapping::Gmf;
  /// Estimate the horizontal tropospheric gradients G_N, G_E (troposphere_gradient.h):
  /// the estimators' receiver state then carries the gradient block
  /// (EstimatorOptions::troposphere_gradients), and the model adds
  /// m_g(e) (G_N cos a + G_E sin a) with its partials to every satellite whose
  /// state layout has the block. Default true: an unmodelled azimuthal asymmetry
  /// of the wet delay moves the kinematic position by up to a centimetre for hours
  /// (measured: doc/studies/config_defaults.md). The method
  /// (method_table.yaml) and the simulated flights (ppp_simulated.yaml, the Monte
  /// Carlo study: the simulator has no gradients) keep them off.
  bool estimate_troposphere_gradients = true;
  /// The estimated zenith wet delay is the one at the ellipsoid (height 0): the
  /// model carries it to the receiver's height with the standard atmosphere's
  /// modified Hopfield wet zenith delay, ZWD(h) = ZWD(0) w(h) / w(0), with the
  /// partial along "up". Default false: the state is the ZWD at the receiver, a
  /// random walk, which holds for a station but not for a receiver that climbs or
  /// descends: the wet delay falls by ~0.6 of its value per 900 m (w(1950 m) /
  /// w(1050 m) = 0.39), 30 times what the method's random walk (3e-5 m/sqrt(s))
  /// allows in 5 min. The simulator's wet delay follows that profile
  /// (simulation/gnss_simulator.h), and config/ppp_simulated.yaml turns this on.
  /// The error of the a-priori dry delay, which the ZWD absorbs, is then scaled
  /// with the wet profile too (doc/evaluation.md).
  bool zwd_at_ellipsoid = false;
  bool solid_earth_tide = true;
  bool ocean_loading = true;  // used only when coefficients are given
  bool phase_windup = true;
  bool satellite_antenna = true;  // satellite PCO + PCV (ANTEX)
  /// Receiver PCO + PCV (ANTEX); the DELTA H/E/N is always applied.
  ReceiverAntennaPolicy receiver_antenna = ReceiverAntennaPolicy::Warn;
  /// A non-GPS frequency missing from the receiver calibration: the GPS stand-in
  /// of receiver_frequency_substitution.h (Gps) or missing (None).
  ReceiverFrequencySubstitution receiver_frequency_substitution = ReceiverFrequencySubstitution::Gps;
  bool shapiro = true;
  bool exclude_eclipse = true;    // reject satellites in the Earth's shadow (umbra or penumbra)
  YawManoeuvreHandling yaw_manoeuvre = YawManoeuvreHandling::Model;  // noon/midnight turns (yaw_manoeuvre.h)
};

/// Phase wind-up state per satellite: the last value [cycles] and its arc, so
/// that the wind-up stays continuous along an arc and restarts on a new one.
/// Explicit state owned by the caller (one per receiver and estimator).
class WindupTracker {
 public:
  WindupTracker() : entries_(static_cast<std::size_t>(kNumGnssSystems) * 100) {}
  /// Last value of `sat` when it belongs to the same arc, else nullopt.
  std::optional<double> previous(const SatelliteId& sat, ArcId arc) const {
    const auto& e = entries_[static_cast<std::size_t>(sat.index())];
    if (!e.valid || e.arc != arc) return std::nullopt;
    return e.cycles;
  }
  void update(const SatelliteId& sat, ArcId arc, double cycles) {
    entries_[static_cast<std::size_t>(sat.index())] = {true, arc, cycles};
  }
  void reset() {
    for (auto& e : entries_) e.valid = false;
  }

 private:
  struct Entry {
    bool valid = false;
    ArcId arc = 0;
    double cycles = 0.0;
  };
  std::vector<Entry> entries_;
};

/// Per-satellite model terms of the last evaluation, for diagnostics and tests
/// (all in metres except where named; sign: as added to the prediction).
struct ModelTerms {
  SatelliteId satellite;
  double geometric_range_m = 0.0;
  double satellite_clock_m = 0.0;       // -c dt_s (product)
  double relativistic_clock_m = 0.0;    // -c dt_rel
  double troposphere_dry_m = 0.0;       // m_d ZHD
  double wet_mapping = 0.0;             // m_w
  double troposphere_gradient_m = 0.0;  // m_g (G_N cos a + G_E sin a); 0 without the gradient block
  double shapiro_m = 0.0;
  double receiver_pcv_m = 0.0;
  double satellite_pcv_m = 0.0;
  double windup_cycles = 0.0;
  double windup_m = 0.0;
  double sagnac_m = 0.0;                // range change due to the Earth rotation during flight
  double nadir_rad = 0.0;
  Eigen::Vector3d satellite_apc_at_transmission_ecef_m = Eigen::Vector3d::Zero();  // unrotated
  /// What the model added to the ephemeris orbit to reach the IF phase centre
  /// (satellite_reference_point.h): the IF PCO for a centre-of-mass orbit, PCO_IF -
  /// PCO_L1 for an L1 orbit, zero for an IF antenna-phase-centre orbit [m, ECEF].
  Eigen::Vector3d satellite_reference_offset_ecef_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d receiver_apc_ecef_m = Eigen::Vector3d::Zero();
};

/// Threading and cost: evaluate() is const and allocation-free once the output
/// vectors have grown (except rejection reason strings); about 3 us per
/// satellite (ppp_bench_measurement_model). It is NOT thread-safe: it fills a
/// satellite-antenna lookup cache (use one model per thread).
class PppMeasurementModel {
 public:
  /// `ephemeris` must outlive the model. `antennas` may be null (no
  /// calibrations: the options must then not ask for the satellite antenna).
  /// `ocean_loading` may be nullptr.
  PppMeasurementModel(const EphemerisSource& ephemeris, std::shared_ptr<const AntennaCalibrationProvider> antennas,
                      const ReceiverAntenna& receiver_antenna, const OceanLoadingCoefficients* ocean_loading,
                      MeasurementModelOptions options = {});

  /// Evaluates one epoch. `arcs[i]` is the arc id of `observations[i]` (same
  /// size). `windup` (nullable) carries the wind-up continuity: pass the same
  /// tracker every epoch; it is updated for each used satellite. `terms`
  /// (nullable) receives the per-satellite model terms of the used satellites.
  /// Its named steps (a rejected satellite leaves at the step that rejects it):
  ///  1. epochTerms: local frame, Sun/Moon, station displacements (tides,
  ///     ocean loading, DELTA H/E/N), troposphere constants, once per epoch;
  ///  2. systemTerms: per system and frequency pair, on first use: IF
  ///     coefficients, wind-up wavelength, sigma factor, receiver PCO (IF);
  ///  3. observedCombinations: the receiver clock of the system and the
  ///     observed IF code and phase (given, or observedIonosphereFree);
  ///  4. satelliteAtEmission: clock and orbit at the emission time, eclipse,
  ///     attitude (satelliteAttitude: nominal, or a noon/midnight turn),
  ///     satellite antenna offset (IF);
  ///  5. signalGeometry: Earth rotation during the flight, line of sight,
  ///     elevation and azimuth, elevation cutoff;
  ///  6. phaseCentreVariations: receiver and satellite PCV (IF);
  ///  7. troposphereMapping: the dry and wet mapping functions;
  ///  8. phaseWindup: the wind-up [cycles], continuous along the arc;
  ///  9. addMeasurement: relativity, Shapiro, the predicted observables, the
  ///     Jacobian row and the sigmas (and modelTerms, on request).
  void evaluate(const std::vector<DualFrequencyObservation>& observations, const std::vector<ArcId>& arcs,
                const ReceiverState& state, WindupTracker* windup, EpochMeasurements& out,
                std::vector<ModelTerms>* terms = nullptr) const;
  /// The same with the epoch's observed IF code and phase computed once by the
  /// caller (`observed[i]` of `observations[i]`, observedIonosphereFree), for an
  /// epoch linearised more than once. Throws std::invalid_argument when the sizes differ.
  void evaluate(const std::vector<DualFrequencyObservation>& observations,
                const std::vector<ObservedIonosphereFree>& observed, const std::vector<ArcId>& arcs,
                const ReceiverState& state, WindupTracker* windup, EpochMeasurements& out,
                std::vector<ModelTerms>* terms = nullptr) const;
  EpochMeasurements evaluate(const std::vector<DualFrequencyObservation>& observations,
                             const std::vector<ArcId>& arcs, const ReceiverState& state,
                             WindupTracker* windup) const {
    EpochMeasurements out;
    evaluate(observations, arcs, state, windup, out);
    return out;
  }

  /// The start model: what the code least squares of the first epoch uses when no
  /// approximate position is known, so that it can iterate from the Earth centre
  /// (after RTKLIB pntpos.c, whose first iteration applies neither troposphere
  /// nor elevation mask). Per satellite the IF code predicted from the geometric
  /// range of the ephemeris position (its reference point as given: no satellite
  /// PCO) with the Earth rotation during the flight, the receiver clock of the
  /// satellite's system and the satellite clock with its relativistic term; no
  /// troposphere, no elevation cutoff, no antenna, tide, wind-up, Shapiro or
  /// eclipse terms (metres to tens of metres: a start, refined by the full model).
  /// Usable at any position, the Earth centre included; one code sigma for all
  /// satellites (the zenith code sigma). Jacobian: -e for the position, 1 for the
  /// system's clock, 0 for the ZWD. Rejected with the reason: no receiver clock
  /// for the system, unusable code, no clock, no orbit.
  void evaluateStart(const std::vector<DualFrequencyObservation>& observations, const ReceiverState& state,
                     EpochMeasurements& out) const;
  /// The same with the epoch's observed IF computed once by the caller (as evaluate's).
  void evaluateStart(const std::vector<DualFrequencyObservation>& observations,
                     const std::vector<ObservedIonosphereFree>& observed, const ReceiverState& state,
                     EpochMeasurements& out) const;

  const MeasurementModelOptions& options() const { return options_; }
  /// Where each antenna calibration came from, e.g. "receiver TRM59800.00 SCIS:
  /// igs20_zim2_gps_trim.atx (TRM59800.00 SCIS not found, using TRM59800.00 NONE)",
  /// "satellite G05 (BLOCK IIR-M G050): igs20_gps_satellites_trim.atx". Satellites
  /// are listed when first used (call after evaluating).
  std::vector<std::string> antennaSources() const;
  /// The receiver calibration in use (nullptr: not found in any file).
  const AntennaCalibration* receiverCalibration() const { return receiver_calibration_; }
  /// Under ReceiverAntennaPolicy::Warn: what is missing and not applied, once
  /// per cause (e.g. "receiver antenna ASH701945E_M SCIS not found in any ANTEX
  /// file: ..."); and, under any policy, each GPS stand-in in use ("receiver
  /// antenna ASH701945E_M SCIS: no Galileo calibration, GPS L1/L2 values used for
  /// E1/E5a ..."); empty when nothing is missing (grows as systems are seen).
  const std::vector<std::string>& receiverAntennaWarnings() const { return receiver_warnings_; }
  /// Satellites whose orbit refers to the L1 antenna phase centre (IGS SSRA)
  /// but that have no satellite calibration for the IF - L1 PCO difference (taken
  /// as zero), one line per satellite with its count of satellite-epochs.
  std::vector<std::string> satelliteReferenceNotes() const;
  /// IF-combined receiver PCO (north, east, up) [m] of a frequency pair of a system.
  std::optional<Eigen::Vector3d> receiverPcoIonosphereFree_m(GnssSystem system, int frequency1, int frequency2,
                                                             double f1_hz, double f2_hz) const;

 private:
  /// The satellite's clock and orbit at the emission time (ephemerisAtEmission).
  struct EmissionEphemeris {
    EphemerisClock clock;
    EphemerisOrbit orbit;
  };
  /// The last emission ephemeris of one satellite, with what it was asked for.
  struct EmissionMemo {
    bool valid = false;
    GnssTime t_rx;
    double code_m = 0.0;
    EmissionEphemeris value;
  };
  struct SatelliteAntennaCache {
    const AntennaCalibration* calibration = nullptr;
    std::string source;
    std::optional<GnssTime> from, until;
    bool looked_up = false;
    bool reported = false;
  };
  // The steps of evaluate() and what they carry (defined with them).
  struct EpochTerms;
  struct SystemTerms;
  struct SatelliteEvaluation;
  /// evaluate() with the observed IF of each observation from `observed` (nullptr: computed here).
  void evaluateEpoch(const std::vector<DualFrequencyObservation>& observations,
                     const std::vector<ObservedIonosphereFree>* observed, const std::vector<ArcId>& arcs,
                     const ReceiverState& state, WindupTracker* windup, EpochMeasurements& out,
                     std::vector<ModelTerms>* terms) const;
  /// evaluateStart() likewise.
  void evaluateStartEpoch(const std::vector<DualFrequencyObservation>& observations,
                          const std::vector<ObservedIonosphereFree>* observed, const ReceiverState& state,
                          EpochMeasurements& out) const;
  EpochTerms epochTerms(const Eigen::Vector3d& marker, const GnssTime& t_rx) const;
  const SystemTerms& systemTerms(const DualFrequencyObservation& o, const EpochTerms& epoch, SystemTerms& st) const;
  bool observedCombinations(SatelliteEvaluation& sv, const EpochTerms& epoch, const ReceiverState& state,
                            EpochMeasurements& out) const;
  bool satelliteAtEmission(SatelliteEvaluation& sv, const EpochTerms& epoch, EpochMeasurements& out) const;
  bool satelliteAttitude(SatelliteEvaluation& sv, const EpochTerms& epoch, EpochMeasurements& out) const;
  bool signalGeometry(SatelliteEvaluation& sv, const EpochTerms& epoch, EpochMeasurements& out) const;
  bool phaseCentreVariations(SatelliteEvaluation& sv, EpochMeasurements& out) const;
  void troposphereMapping(SatelliteEvaluation& sv, const EpochTerms& epoch) const;
  bool phaseWindup(SatelliteEvaluation& sv, const EpochTerms& epoch, const WindupTracker* windup,
                   EpochMeasurements& out) const;
  void addMeasurement(const SatelliteEvaluation& sv, const EpochTerms& epoch, const ReceiverState& state,
                      WindupTracker* windup, EpochMeasurements& out, std::vector<ModelTerms>* terms) const;
  ModelTerms modelTerms(const SatelliteEvaluation& sv, const EpochTerms& epoch, double shapiro_m,
                        double relativistic_s) const;

  /// The satellite's clock and orbit at the emission time of a code observed at t_rx
  /// (ephemerisAtEmission), from the memo when the same satellite, t_rx and code were
  /// asked last (an estimator linearises an epoch more than once); nullopt after a
  /// rejection through `reject`.
  template <typename Reject>
  std::optional<EmissionEphemeris> emissionEphemeris(const SatelliteId& sat, const GnssTime& t_rx, double code_m,
                                                     Reject&& reject) const;
  const AntennaCalibration* satelliteCalibration(const SatelliteId& sat, const GnssTime& t) const;
  void warnReceiverAntenna(std::string text) const;

  const EphemerisSource& ephemeris_;
  std::shared_ptr<const AntennaCalibrationProvider> antennas_;
  ReceiverAntenna receiver_antenna_;
  const AntennaCalibration* receiver_calibration_ = nullptr;
  std::string receiver_source_;
  std::optional<OceanLoadingCoefficients> ocean_loading_;
  MeasurementModelOptions options_;
  mutable std::vector<SatelliteAntennaCache> satellite_cache_;  // lookup cache (not model state)
  mutable std::vector<EmissionMemo> emission_memo_;             // per satellite index (not model state)
  mutable std::shared_ptr<const EpochTerms> last_epoch_terms_;  // of the last evaluate() (not model state)
  mutable std::vector<std::string> receiver_warnings_;          // reported once each
  mutable std::vector<std::size_t> l1_reference_without_calibration_;  // per satellite index: counted
};

}  // namespace ppp
