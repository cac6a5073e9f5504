#pragma once
// MeasurementFunction: how the estimators ask the (single) measurement model to
// linearise one epoch at a receiver state. The pipeline builds one per epoch,
// capturing that epoch's dual-frequency observations and arc ids; the EKF and
// the code least squares call it again at each new linearisation point
// (iterations), so they never compute physics themselves.
#include <functional>

#include "ppp_bayes_tree/ppp/model/satellite_measurement.h"

namespace ppp {

/// Returns the epoch's measurements linearised at `state` (predicted IF code and
/// phase, Jacobian, sigmas), plus the satellites the model left out, with reasons.
using MeasurementFunction = std::function<EpochMeasurements(const ReceiverState& state)>;

}  // namespace ppp
