#pragma once
// Monte Carlo flight records: the per-flight results of a study (or of one shard
// of it: MonteCarloOptions::first_flight) written EXACTLY (binary, every double
// and float as stored), so that shards run anywhere merge into the study: the
// merged flights in index order give summarizeMonteCarlo the same input as one
// run over all flights, hence the same tables (CDFs, first-window statistics,
// convergence times) bit for bit.
//
// The records hold no wall-clock times (simulate_s, ekf_s, smoother_s stay 0),
// so that a shard's records are the same bytes whoever ran it; the flight setup
// (profile, start, origin) is recomputed from the study's options and the flight
// index when reading, and checked against the stored flight seed.
//
// Layout (little-endian, as written on the machines we support): the magic
// "PPPMCR01", a u32 flight count, then per flight its index (i32), seed (u64),
// failure text, drawn-parameter texts, counts, and the per-epoch arrays of
// MonteCarloFlightRun (u64 length, then the elements).
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/monte_carlo.h"

namespace ppp {

/// Throws std::runtime_error when the file cannot be written.
void writeMonteCarloFlightRecords(const std::vector<MonteCarloFlightRun>& flights, const std::string& path);

/// Reads records written by writeMonteCarloFlightRecords for a study with
/// `options` (same seed, profiles, duration...). Throws FileOpenError, or
/// ParseError naming the file and the byte offset (line field) of a truncated
/// or foreign file, or of a flight whose seed is not the study's.
std::vector<MonteCarloFlightRun> readMonteCarloFlightRecords(const std::string& path,
                                                             const MonteCarloOptions& options);

/// The study over all flights 0 .. study.flights - 1 from shards (any order):
/// flights sorted by index, summarizeMonteCarlo over them; result.options is
/// `study` (first_flight 0). Throws std::invalid_argument naming a flight index
/// that is missing, repeated or outside the study.
MonteCarloResult mergeMonteCarloShards(const MonteCarloOptions& study,
                                       std::vector<std::vector<MonteCarloFlightRun>> shards);

}  // namespace ppp
