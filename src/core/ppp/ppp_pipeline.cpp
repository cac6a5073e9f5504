#include "ppp_bayes_tree/ppp/ppp_pipeline.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex_obs_reader.h"
#include "ppp_bayes_tree/io/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/ubx_observation_source.h"
#include "ppp_bayes_tree/models/broadcast_products.h"
#include "ppp_bayes_tree/ppp/antenna_model_consistency.h"
#include "ppp_bayes_tree/ppp/phase_bias_consistency.h"
#include "ppp_bayes_tree/models/clock_wide_lane_bias_provider.h"
#include "ppp_bayes_tree/io/rinex_clock_reader.h"
#include "ppp_bayes_tree/ppp/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ppp/product_set.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

/// The products an observation file needs: the systems processed and the span of
/// its epochs (one extra pass over the file, a few ms; without epochs no window).
RecordFilter productFilter(const std::string& obs_path, const std::vector<GnssSystem>& systems) {
  RecordFilter filter;
  filter.systems = systems;
  try {
    RinexObsReader reader = RinexObsReader::open(obs_path);
    ObsEpoch epoch;
    while (reader.next(epoch)) {
      if (!filter.first || epoch.time < *filter.first) filter.first = epoch.time;
      if (!filter.last || *filter.last < epoch.time) filter.last = epoch.time;
    }
  } catch (const std::exception&) {  // reported by the main pass; load without a window
    filter.first.reset();
    filter.last.reset();
  }
  return filter;
}

/// Running sums for one satellite's residual statistics.
struct ResidualAccumulator {
  std::size_t n = 0, rejections = 0;
  double code_sum = 0, code_sq = 0, phase_sum = 0, phase_sq = 0, phase_max = 0;
  double el_min = 90.0, el_max = 0.0;
};

/// The wide-lane satellite biases in the headers of integer-recovery clock
/// files (GRG convention); nullptr unless every clock file lists them.
std::unique_ptr<const ClockWideLaneBiasProvider> integerRecoveryClockBiases(const std::vector<std::string>& clock_files,
                                                                           std::vector<std::string>& problems) {
  if (clock_files.empty()) return nullptr;
  std::map<SatelliteId, double> all;
  for (const auto& path : clock_files) {
    RinexClockReadOptions options;
    options.keep_receiver_clocks = false;
    const RinexClockFile file = readRinexClock(path, options);
    ClockWideLaneBiases wl = parseClockWideLaneBiases(file.header.comments);
    for (const auto& p : wl.problems) problems.push_back(fileBaseName(path) + ": " + p);
    if (wl.wide_lane_cycles.empty()) return nullptr;
    all.insert(wl.wide_lane_cycles.begin(), wl.wide_lane_cycles.end());
  }
  return std::make_unique<const ClockWideLaneBiasProvider>(std::move(all), fileBaseName(clock_files.front()));
}

}  // namespace

std::string toString(RejectionStage stage) {
  switch (stage) {
    case RejectionStage::Signals: return "signals";
    case RejectionStage::Arcs: return "arcs";
    case RejectionStage::Model: return "model";
  }
  return "unknown";
}

std::string toString(const RejectionKey& key) { return toString(key.stage) + ": " + toString(key.reason); }

struct PppPipeline::Impl {
  /// PPP-AR biases from integer-recovery clocks; declared before `processor`,
  /// which holds a pointer to it, so that it is destroyed after it.
  std::unique_ptr<const ClockWideLaneBiasProvider> clock_wide_lane_biases;
  std::unique_ptr<ObservationSource> source;
  PppProducts products;
  std::optional<std::string> bias_file_name;  // for the code-reference note
  std::unique_ptr<PppEpochProcessor> processor;
  std::vector<std::string> load_notes;
  /// What went wrong reading the products (each becomes a problem of every run).
  std::vector<std::string> load_problems;
  bool ran = false;

  void start(const PppConfig& config) {
    processor = std::make_unique<PppEpochProcessor>(source->header(), config, *products.ephemeris,
                                                    products.antennas, products.biases.get(),
                                                    products.ocean ? &*products.ocean : nullptr);
  }
};

PppPipeline::PppPipeline(std::unique_ptr<ObservationSource> observations, PppProducts products, PppConfig config)
    : config_(std::move(config)), impl_(std::make_unique<Impl>()) {
  if (!observations || !products.ephemeris)
    throw std::invalid_argument("pipeline inputs: an observation source and an ephemeris source are required");
  Impl& d = *impl_;
  d.source = std::move(observations);
  d.products = std::move(products);
  d.load_notes = d.products.notes;
  d.start(config_);
}

PppPipeline::PppPipeline(const PppInputFiles& files, PppConfig config)
    : config_(std::move(config)), impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  if (files.atx.empty()) throw std::runtime_error("no ANTEX file given (antenna calibrations are required)");
  RecordFilter filter;
  if (files.obs_format == ObservationFormat::Rtcm3 || files.obs_format == ObservationFormat::Ubx) {
    if (files.obs_format == ObservationFormat::Rtcm3) {
      Rtcm3DecoderOptions rtcm_options;
      rtcm_options.reference_time = files.rtcm_reference_time;
      d.source = std::make_unique<RtcmObservationSource>(files.obs, rtcm_options);
    } else {
      d.source = std::make_unique<UbxObservationSource>(files.obs);
    }
    filter.systems = config_.signals.systems;
    const RinexObsHeader& h = d.source->header();
    if (h.time_of_first_obs) filter.first = h.time_of_first_obs->time;
    if (h.time_of_last_obs) filter.last = h.time_of_last_obs->time;
  } else {
    d.source = std::make_unique<RinexObservationSource>(files.obs);
    filter = productFilter(files.obs, config_.signals.systems);
  }
  std::shared_ptr<const BiasProvider> ssr_biases;
  if (!files.nav.empty()) {
    BroadcastProducts broadcast =
        loadBroadcastProducts(files.nav, files.ssr, files.ssr_reference, config_.ssr, files.rtcm_reference_time);
    d.products.ephemeris = std::move(broadcast.ephemeris);
    ssr_biases = std::move(broadcast.ssr_biases);
    d.load_notes.insert(d.load_notes.end(), broadcast.notes.begin(), broadcast.notes.end());
    d.load_problems.insert(d.load_problems.end(), broadcast.problems.begin(), broadcast.problems.end());
  } else {
    PreciseEphemerisOptions ephemeris_options;
    ephemeris_options.check_products = files.check_products;
    auto ephemeris =
        std::make_shared<PreciseEphemeris>(PreciseEphemeris::load(files.sp3, files.clk, filter, ephemeris_options));
    if (!ephemeris->mergeReport().problems().empty() || !ephemeris->mergeReport().counters().empty())
      d.load_notes.push_back("products merged: " + ephemeris->mergeReport().summary(5));
    for (const auto& p : ephemeris->mergeReport().problems()) d.load_problems.push_back(p.reason);
    if (ephemeris->mergeReport().problemCount() > ephemeris->mergeReport().problems().size())
      d.load_problems.push_back("... and " +
                                std::to_string(ephemeris->mergeReport().problemCount() -
                                               ephemeris->mergeReport().problems().size()) +
                                " more problem(s) of the precise products");
    d.products.ephemeris = std::move(ephemeris);
  }
  auto set = std::make_shared<ProductSet>(ProductSet::load({files.atx, files.bias, files.blq, config_.signals.systems}));
  for (const auto& n : set->notes()) d.load_notes.push_back(n);
  d.load_problems.insert(d.load_problems.end(), set->problems().begin(), set->problems().end());
  d.products.antennas = set->antennas();
  if (set->biases() != nullptr) {
    d.products.biases = std::shared_ptr<const BiasProvider>(set, set->biases());
    d.bias_file_name = fileBaseName(*files.bias);
  } else if (ssr_biases) {
    d.products.biases = ssr_biases;
    d.load_notes.push_back("code biases: " + ssr_biases->describeSource());
  }
  if (files.blq) {
    const RinexObsHeader& h = d.source->header();
    const OceanLoadingLookup found = set->oceanLoading(h.marker_name.empty() ? stationName() : h.marker_name);
    if (found.coefficients) d.products.ocean = *found.coefficients;
    d.load_notes.push_back(found.note);
  }
  d.start(config_);
  // The satellite antenna model the products were made with against the ANTEX's.
  std::optional<AntennaModelCheck> antenna_model;
  if (set->antennas() && !(files.sp3.empty() && files.clk.empty())) {
    std::vector<std::string> product_models;
    for (const auto* list : {&files.sp3, &files.clk})
      for (const auto& f : *list) {
        try {
          product_models.push_back(productAntennaModel(f));
        } catch (const std::exception&) {  // unreadable products are reported by their readers
        }
      }
    antenna_model = checkAntennaModelConsistency(product_models, satelliteAntennaModels(*set->antennas()));
    d.load_notes.push_back((antenna_model->different() ? "warning: " : "") + antenna_model->text());
  }
  if (config_.ambiguity_resolution.enabled && antenna_model && antenna_model->different() &&
      !config_.ambiguity_resolution.allow_antenna_model_mismatch) {
    d.load_notes.push_back("ambiguity resolution: refused: " + antenna_model->text() +
                           ": float (ambiguity_resolution.allow_antenna_model_mismatch: true to fix anyway)");
  } else if (config_.ambiguity_resolution.enabled) {
    if (antenna_model && antenna_model->different())
      d.load_notes.push_back("ambiguity resolution: antenna model mismatch allowed (allow_antenna_model_mismatch)");
    // PPP-AR needs phase OSBs from the clocks' own analysis centre.
    bool has_phase = false;
    if (set->biasFile())
      for (const auto& r : set->biasFile()->records)
        if (r.type == BiasType::OSB && r.obs1.type == ObservableType::CarrierPhase) {
          has_phase = true;
          break;
        }
    const PhaseBiasCheck check = checkPhaseBiasConsistency(files.clk, files.bias, has_phase);
    if (check.consistent()) {
      d.load_notes.push_back("ambiguity resolution: " + check.text());
      d.processor->setPhaseBiases(set->biases());
    } else if (auto wl = integerRecoveryClockBiases(files.clk, d.load_problems)) {
      d.load_notes.push_back("ambiguity resolution: integer-recovery clocks with " + std::to_string(wl->size()) +
                             " wide-lane satellite biases in the clock header");
      d.processor->setPhaseBiases(wl.get());
      d.clock_wide_lane_biases = std::move(wl);
    } else {
      d.load_notes.push_back("ambiguity resolution: " + check.text());
    }
  }
}

PppPipeline::PppPipeline(const PppInMemoryInputs& inputs, PppConfig config)
    : config_(std::move(config)), impl_(std::make_unique<Impl>()) {
  if (!inputs.header || !inputs.epochs || !inputs.products)
    throw std::invalid_argument("in-memory pipeline inputs: header, epochs and products are required");
  Impl& d = *impl_;
  d.source = std::make_unique<InMemoryObservationSource>(*inputs.header, *inputs.epochs, inputs.name);
  d.products.ephemeris = std::shared_ptr<const EphemerisSource>(std::shared_ptr<void>(), inputs.products);
  if (!inputs.antex.empty()) d.products.antennas = std::make_shared<const AntexCalibrations>(inputs.antex);
  d.load_notes.push_back("observations: " + inputs.name + " (in-process epochs)");
  d.start(config_);
  if (config_.ambiguity_resolution.enabled) {
    if (inputs.phase_biases) {
      d.load_notes.push_back("ambiguity resolution: " + inputs.phase_biases->describeSource());
      d.processor->setPhaseBiases(inputs.phase_biases);
    } else {
      d.load_notes.push_back("ambiguity resolution: no phase biases given: float");
    }
  }
}

PppPipeline::~PppPipeline() = default;

const RinexObsHeader& PppPipeline::header() const { return impl_->source->header(); }

std::string PppPipeline::stationName() const {
  std::string name = impl_->source->header().marker_name;
  if (name.empty()) name = fileBaseName(impl_->source->name());
  name = name.substr(0, std::min<std::size_t>(4, name.size()));
  for (auto& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return name;
}

std::vector<std::string> PppPipeline::notes() const {
  std::vector<std::string> n = impl_->load_notes;
  for (const auto& s : impl_->processor->antennaSources()) n.push_back("antenna " + s);
  for (const auto& w : impl_->processor->receiverAntennaWarnings()) n.push_back("warning: " + w);
  for (const auto& w : impl_->processor->satelliteReferenceNotes()) n.push_back("warning: " + w);
  return n;
}

const std::vector<std::string>& PppPipeline::receiverAntennaWarnings() const {
  return impl_->processor->receiverAntennaWarnings();
}

double PppPipeline::progress() const { return impl_->source->progress(); }

PppRunSummary PppPipeline::run(EpochEstimator& estimator, const EpochCallback& on_epoch) {
  Impl& d = *impl_;
  PppRunSummary summary;
  std::optional<GnssTime> first_solved;  // for the time to first fix
  summary.estimator = estimator.name();
  if (d.ran) {
    summary.problems.push_back("the pipeline has already run (the observation file is streamed once)");
    return summary;
  }
  d.ran = true;
  summary.problems = d.load_problems;
  // Satellites rejected, for naming those an input problem took out of the run.
  std::map<SatelliteId, std::pair<std::size_t, std::string>> rejected_epochs;  // count, first reason
  const auto wall_start = std::chrono::steady_clock::now();
  const RinexObsHeader& header = d.source->header();
  if (header.approx_position_ecef_m && header.approx_position_ecef_m->norm() > 1e6)
    estimator.setApproximatePosition(*header.approx_position_ecef_m);

  // Code-reference notes, merged over epochs: text before a trailing
  // satellite list -> union of the satellites.
  std::map<std::string, std::set<std::string>> code_notes;
  std::map<SatelliteId, ResidualAccumulator> acc;
  PppEpochProcessor& processor = *d.processor;
  ObsEpoch epoch;
  PppEpochRecord rec;
  std::vector<std::string> selection_notes;

  for (;;) {
    const ObservationRead read = d.source->next(epoch);
    if (read == ObservationRead::End) break;
    if (read == ObservationRead::Error) {
      const ObservationProblem e = d.source->error().value_or(ObservationProblem{d.source->name(), 0, "read error"});
      throw ParseError(e.file, e.line, e.reason);
    }
    ++summary.epochs_read;
    rec = processor.process(epoch, estimator, &selection_notes);
    if (rec.refused) {
      ++summary.epochs_refused;
      summary.problems.push_back("epoch " + epoch.time.toString() + " refused: " + rec.reason);
      if (on_epoch) on_epoch(rec);
      continue;
    }
    if (rec.gap_s) ++summary.data_gaps;
    for (const auto& n : selection_notes) {
      const auto colon = n.rfind(": ");
      std::istringstream sats(colon == std::string::npos ? std::string() : n.substr(colon + 2));
      std::vector<std::string> tokens;
      std::string tok;
      bool all_sats = colon != std::string::npos;
      while (sats >> tok) {
        all_sats &= tok.size() == 3 && std::isalpha(static_cast<unsigned char>(tok[0])) &&
                    std::isdigit(static_cast<unsigned char>(tok[1])) && std::isdigit(static_cast<unsigned char>(tok[2]));
        tokens.push_back(tok);
      }
      if (all_sats && !tokens.empty()) {
        code_notes[n.substr(0, colon)].insert(tokens.begin(), tokens.end());
      } else {
        code_notes[n];
      }
    }
    summary.arcs += static_cast<std::size_t>(rec.new_arcs);
    summary.slips += static_cast<std::size_t>(rec.slips);
    for (const auto& x : rec.rejected)
      if (x.stage == RejectionStage::Model) acc[x.satellite].rejections++;
    switch (rec.status) {
      case EpochStatus::Ok:
        ++summary.epochs_solved;
        if (!first_solved) first_solved = rec.solution.time;
        if (rec.solution.status == SolutionStatus::PppFixed) {
          ++summary.epochs_fixed;
          if (!summary.time_to_first_fix_s) summary.time_to_first_fix_s = rec.solution.time - *first_solved;
        }
        break;
      case EpochStatus::NoSolution: ++summary.epochs_no_solution; break;
      case EpochStatus::Failed: ++summary.epochs_failed; break;
    }
    if (rec.status == EpochStatus::Ok && rec.solution.position_ecef_m) {
      for (const auto& res : rec.residuals) {
        auto& a = acc[res.satellite];
        ++a.n;
        a.code_sum += res.code_postfit_m;
        a.code_sq += res.code_postfit_m * res.code_postfit_m;
        a.phase_sum += res.phase_postfit_m;
        a.phase_sq += res.phase_postfit_m * res.phase_postfit_m;
        a.phase_max = std::max(a.phase_max, std::abs(res.phase_postfit_m));
        a.el_min = std::min(a.el_min, res.elevation_rad * kRadToDeg);
        a.el_max = std::max(a.el_max, res.elevation_rad * kRadToDeg);
      }
    }
    for (const auto& x : rec.rejected) summary.rejection_counts[{x.stage, x.reason}]++;
    for (const auto& x : rec.rejected) {
      auto& r = rejected_epochs[x.satellite];
      if (r.first++ == 0) r.second = x.text();
    }
    if (rec.status != EpochStatus::Ok) summary.no_solution_counts[rec.no_solution_reason]++;
    if (rec.estimator_reset) ++summary.estimator_resets;
    if (rec.solution.integrity == SolutionIntegrity::Inconsistent) ++summary.epochs_inconsistent;
    if (on_epoch) on_epoch(rec);
  }
  estimator.arcsEnded(processor.finish());

  for (const auto& p : d.source->problems())
    summary.problems.push_back(p.file + " line " + std::to_string(p.line) + ": " + p.reason);
  if (!summary.problems.empty()) {
    // With input problems, name the satellites the run never used.
    std::string dropped;
    for (const auto& [sat, r] : rejected_epochs) {
      auto it = acc.find(sat);
      if (it != acc.end() && it->second.n > 0) continue;
      dropped += (dropped.empty() ? "" : "; ") + sat.toString() + " (" + std::to_string(r.first) +
                 " epoch(s), first: " + r.second + ")";
    }
    if (!dropped.empty()) summary.problems.push_back("satellites never used: " + dropped);
  }
  for (const auto& [sat, a] : acc) {
    SatelliteResidualStatistics st;
    st.satellite = sat;
    st.count = a.n;
    st.rejections = a.rejections;
    if (a.n > 0) {
      st.code_mean_m = a.code_sum / a.n;
      st.code_rms_m = std::sqrt(a.code_sq / a.n);
      st.phase_mean_m = a.phase_sum / a.n;
      st.phase_rms_m = std::sqrt(a.phase_sq / a.n);
      st.phase_max_abs_m = a.phase_max;
      st.min_elevation_deg = a.el_min;
      st.max_elevation_deg = a.el_max;
    }
    summary.residual_statistics.push_back(st);
  }
  summary.notes = notes();
  for (const auto& [text, sats] : code_notes) {
    std::string note = "code reference: " + text;
    if (!sats.empty()) note += ":";
    for (const auto& sat : sats) note += " " + sat;
    summary.notes.push_back(note);
  }
  if (code_notes.empty() && d.products.biases)
    summary.notes.push_back("code reference: codes aligned to the clock reference by the OSB of " +
                            d.bias_file_name.value_or(d.products.biases->describeSource()));
  summary.processing_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return summary;
}

}  // namespace ppp
