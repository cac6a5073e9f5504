#pragma once
// Helpers of the simulator tests: feed a simulated flight through the same
// pipeline as real data (SignalSelector -> PppMeasurementModel) at the TRUE
// state and collect the residuals.
#include <cmath>
#include <vector>

#include "ppp_bayes_tree/ppp/model/ppp_measurement_model.h"
#include "ppp_bayes_tree/ppp/model/signal_selection.h"
#include "ppp_bayes_tree/simulation/gnss_simulator.h"

namespace ppp::test {

struct TrueStateResidual {
  SatelliteId satellite;
  ArcId arc = 0;
  double elevation_rad = 0.0;
  double code_m = 0.0;   // observed - predicted IF code
  double phase_m = 0.0;  // observed - predicted IF phase - truth arc bias
  const SignalTruth* signal = nullptr;
};

/// Residuals of every observation at the true state, with the truth arcs and
/// the given products (default: the flight's error-free truth products).
inline std::vector<TrueStateResidual> trueStateResiduals(const SimulatedFlight& f, bool use_estimator_products = false,
                                                         double cutoff_rad = 7.0 * kDegToRad) {
  MeasurementModelOptions options = f.model_options;
  options.elevation_cutoff_rad = cutoff_rad;
  const PppMeasurementModel model(use_estimator_products ? f.products : f.truth_products, {},
                                  ReceiverAntenna::fromHeader(f.header), nullptr, options);
  SignalSelector selector(f.header, SignalSelectionOptions{}, nullptr);
  WindupTracker windup;
  std::vector<TrueStateResidual> out;
  SignalSelectionResult sel;
  EpochMeasurements meas;
  std::vector<ArcId> arcs;
  for (std::size_t k = 0; k < f.epochs.size(); ++k) {
    selector.select(f.epochs[k], sel);
    const TruthEpoch& te = f.truth[k];
    arcs.clear();
    for (const auto& o : sel.observations) {
      ArcId a = 0;
      for (const auto& s : te.signals)
        if (s.satellite == o.satellite) a = s.arc;
      arcs.push_back(a);
    }
    ReceiverState state;
    state.position_ecef_m = te.trajectory.position_ecef_m;
    state.zwd_m = te.zwd_m;
    state.setClock_m(GnssSystem::GPS, te.clock_m);  // the simulator observes GPS only
    model.evaluate(sel.observations, arcs, state, &windup, meas);
    for (const auto& m : meas.used) {
      TrueStateResidual r;
      r.satellite = m.satellite;
      r.arc = m.arc;
      r.elevation_rad = m.elevation_rad;
      r.code_m = m.codeResidual_m();
      r.phase_m = m.phaseResidualWithoutBias_m() - f.arcs.at(m.arc - 1).bias_if_m;
      for (const auto& s : te.signals)
        if (s.satellite == m.satellite) r.signal = &s;
      out.push_back(r);
    }
  }
  return out;
}

inline double sampleSigma(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m += x;
  m /= static_cast<double>(v.size());
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

inline SimulationConfig shortConfig(FlightProfile profile, double minutes, ErrorModelConfig errors) {
  SimulationConfig c;
  c.profile = profile;
  c.duration_s = minutes * 60.0;
  c.errors = errors;
  return c;
}

}  // namespace ppp::test
