#include "ppp_bayes_tree/ppp/pipeline/ppp_pipeline.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"
#include "ppp_bayes_tree/io/ubx/ubx_observation_source.h"
#include "ppp_bayes_tree/models/broadcast_products.h"
#include "ppp_bayes_tree/ppp/pipeline/ppp_epoch_processor.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/types/constants.h"

namespace ppp {
namespace {

/// "the window --start S --end E holds no epoch of F (its epochs: A to B)".
std::string emptyWindowText(const std::string& path, const ObservationWindow& window, const GnssTime& file_first,
                            const GnssTime& file_last) {
  std::string bounds;
  if (window.start) bounds += " --start " + window.start->toString(TimeSystem::GPS, 0);
  if (window.end) bounds += " --end " + window.end->toString(TimeSystem::GPS, 0);
  const std::string span = window.end && file_first >= *window.end
                               ? "its epochs start at " + file_first.toString(TimeSystem::GPS, 0)
                               : "its epochs: " + file_first.toString(TimeSystem::GPS, 0) + " to " +
                                     file_last.toString(TimeSystem::GPS, 0);
  return "the window" + bounds + " holds no epoch of " + path + " (" + span + ")";
}

/// What one pass over an observation file finds before the run: its epochs' span
/// and the satellites observed (inside the window). Unset when the file cannot be read.
struct ObservationScan {
  std::optional<GnssTime> first, last;
  std::optional<std::set<SatelliteId>> satellites;
};

/// One extra pass over an observation file (a few ms). With a window: the span and
/// satellites of the epochs inside it (the pass stops after its end); a window that
/// holds no epoch of a readable file is refused, with the file's span.
ObservationScan scanObservations(const std::string& obs_path, const ObservationWindow& window) {
  ObservationScan scan;
  std::optional<GnssTime> file_first, file_last;
  std::set<SatelliteId> satellites;
  try {
    RinexObsReader reader = RinexObsReader::open(obs_path);
    ObsEpoch epoch;
    while (reader.next(epoch)) {
      if (!file_first || epoch.time < *file_first) file_first = epoch.time;
      if (!file_last || *file_last < epoch.time) file_last = epoch.time;
      if (window.end && epoch.time >= *window.end) break;
      if (!window.contains(epoch.time)) continue;
      if (!scan.first || epoch.time < *scan.first) scan.first = epoch.time;
      if (!scan.last || *scan.last < epoch.time) scan.last = epoch.time;
      for (const auto& sat : epoch.satellites) satellites.insert(sat.satellite);
    }
  } catch (const std::exception&) {
    return {};
  }
  if (window.bounded() && !scan.first && file_first)
    throw std::runtime_error(emptyWindowText(obs_path, window, *file_first, *file_last));
  scan.satellites = std::move(satellites);
  return scan;
}

/// Running sums for one satellite's residual statistics.
struct ResidualAccumulator {
  std::size_t n = 0, rejections = 0;
  std::size_t screened_out = 0;  // rejections by the residual tests (code and phase, prefit and postfit)
  double code_sum = 0, code_sq = 0, phase_sum = 0, phase_sq = 0, phase_max = 0;
  double el_min = 90.0, el_max = 0.0;
};

bool isResidualTest(RejectionReason reason) {
  switch (reason) {
    case RejectionReason::CodeLeastSquaresOutlier:
    case RejectionReason::PrefitCode:
    case RejectionReason::PrefitPhase:
    case RejectionReason::PostfitCode:
    case RejectionReason::PostfitPhase: return true;
    default: return false;
  }
}

/// Fewest residual-test rejections of a GLONASS satellite that can point to a wrong channel.
constexpr std::size_t kSuspectChannelMinRejections = 10;

/// A GLONASS satellite rejected by the residual tests in more epochs than it was used in:
/// its frequencies (from its channel) may be wrong.
bool suspectChannel(std::size_t used, std::size_t screened_out) {
  return screened_out >= kSuspectChannelMinRejections && screened_out > used;
}

std::string suspectChannelNote(const SatelliteId& sat, std::size_t used, std::size_t screened_out,
                               std::optional<int> channel) {
  const std::string k = channel ? (*channel > 0 ? "+" : "") + std::to_string(*channel) : std::string("unknown");
  return "warning: " + sat.toString() + " (channel " + k + ") rejected by the residual tests " +
         std::to_string(screened_out) + " times, used in " + std::to_string(used) +
         " epochs: a wrong frequency channel gives such residuals; check GLONASS SLOT / FRQ # against the "
         "navigation records";
}

/// The residual statistics' summary of a run, per satellite: the residuals of the
/// solved epochs, the model-stage rejections and those of the residual tests; at the
/// end the statistics and the warnings of GLONASS satellites with a suspect channel.
class ResidualSummary {
 public:
  /// One processed epoch: its rejections and, when solved with a position, its residuals.
  void add(const PppEpochRecord& rec) {
    for (const auto& x : rec.rejected) {
      if (x.stage == RejectionStage::Model) acc_[x.satellite].rejections++;
      if (isResidualTest(x.reason)) acc_[x.satellite].screened_out++;
    }
    if (rec.status != EpochStatus::Ok || !rec.solution.position_ecef_m) return;
    for (const auto& res : rec.residuals) {
      auto& a = acc_[res.satellite];
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

  /// Whether `sat` had residuals in a solved epoch.
  bool used(const SatelliteId& sat) const {
    const auto it = acc_.find(sat);
    return it != acc_.end() && it->second.n > 0;
  }

  /// One row per satellite with residuals or rejections.
  std::vector<SatelliteResidualStatistics> statistics() const {
    std::vector<SatelliteResidualStatistics> out;
    for (const auto& [sat, a] : acc_) {
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
      out.push_back(st);
    }
    return out;
  }

  /// A warning per GLONASS satellite the residual tests rejected in more epochs than
  /// it was used in, with its channel (`channels`: those the run used).
  std::vector<std::string> suspectChannelNotes(const GlonassChannels& channels) const {
    std::vector<std::string> out;
    for (const auto& [sat, a] : acc_)
      if (sat.system == GnssSystem::GLONASS && suspectChannel(a.n, a.screened_out))
        out.push_back(suspectChannelNote(sat, a.n, a.screened_out, channels.channel(sat.prn)));
    return out;
  }

 private:
  std::map<SatelliteId, ResidualAccumulator> acc_;
};

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
  /// The products of a file run (and the phase-bias provider the processor
  /// points to); declared before `processor`, so that it is destroyed after it.
  std::optional<ProductAssembly> assembly;
  const BiasProvider* phase_biases = nullptr;  // what the processor was given (PPP-AR)
  std::unique_ptr<ObservationSource> source;
  PppProducts products;
  std::optional<std::string> bias_file_name;  // for the code-reference note
  std::unique_ptr<PppEpochProcessor> processor;
  std::vector<std::string> load_notes;
  /// What went wrong reading the products (each becomes a problem of every run).
  std::vector<std::string> load_problems;
  bool ran = false;

  void start(const PppConfig& config) {
    if (!products.ephemeris)
      throw std::invalid_argument("pipeline inputs: no orbit and clock products (an ephemeris source) to solve with");
    processor = std::make_unique<PppEpochProcessor>(source->header(), config, *products.ephemeris,
                                                    products.antennas, products.biases.get(),
                                                    products.ocean ? &*products.ocean : nullptr);
    if (phase_biases) processor->setPhaseBiases(phase_biases);
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
  d.phase_biases = d.products.phase_biases.get();
  d.start(config_);
}

PppInputFiles preciseInputFiles(std::string obs, std::vector<std::string> sp3, std::vector<std::string> clk,
                                std::vector<std::string> atx, std::optional<std::string> bias,
                                std::optional<std::string> blq) {
  PppInputFiles files;
  files.obs = std::move(obs);
  files.sp3 = std::move(sp3);
  files.clk = std::move(clk);
  files.atx = std::move(atx);
  files.bias = std::move(bias);
  files.blq = std::move(blq);
  return files;
}

PppPipeline::PppPipeline(const PppInputFiles& files, PppConfig config)
    : config_(std::move(config)), impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  if (files.atx.empty()) throw std::runtime_error("no ANTEX file given (antenna calibrations are required)");
  ProductAssemblyInputs in;
  if (files.obs_format == ObservationFormat::Rtcm3 || files.obs_format == ObservationFormat::Ubx) {
    if (files.obs_format == ObservationFormat::Rtcm3) {
      Rtcm3DecoderOptions rtcm_options;
      rtcm_options.reference_time = files.rtcm_reference_time;
      d.source = std::make_unique<RtcmObservationSource>(files.obs, rtcm_options);
    } else {
      d.source = std::make_unique<UbxObservationSource>(files.obs);
    }
    const RinexObsHeader& h = d.source->header();
    if (h.time_of_first_obs) in.first = h.time_of_first_obs->time;
    if (h.time_of_last_obs) in.last = h.time_of_last_obs->time;
  } else {
    d.source = std::make_unique<RinexObservationSource>(files.obs);
    ObservationScan scan = scanObservations(files.obs, files.window);
    in.first = scan.first;
    in.last = scan.last;
    in.observed_satellites = std::move(scan.satellites);
  }
  if (const std::string why = fileProductInputsProblem(productInputsGiven(files)); !why.empty())
    throw std::invalid_argument(why);
  if (files.window.bounded()) {
    d.source = std::make_unique<TimeWindowObservationSource>(std::move(d.source), files.window);
    if (in.first && files.window.start && *in.first < *files.window.start) in.first = files.window.start;
    if (in.last && files.window.end && *in.last >= *files.window.end) in.last = *files.window.end - 1e-3;
  }
  static_cast<OrbitClockFiles&>(in) = files;  // whichever source they make
  in.stream_reference_time = files.rtcm_reference_time;
  in.check_products = files.check_products;
  in.atx = files.atx;
  in.bias = files.bias;
  in.blq = files.blq;
  in.observation_glonass_channels = d.source->header().glonass_channels;
  d.assembly = ProductAssembly::assemble(in, config_);
  const ProductAssembly& products = *d.assembly;
  config_ = products.config();
  const RinexObsHeader& h = d.source->header();
  d.products = products.products(h.marker_name.empty() ? stationName() : h.marker_name);
  d.load_notes = d.products.notes;
  d.load_problems = products.problems();
  if (files.bias && products.codeBiases()) d.bias_file_name = fileBaseName(*files.bias);
  d.phase_biases = products.phaseBiases();
  d.start(config_);
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
      d.phase_biases = inputs.phase_biases;
      d.processor->setPhaseBiases(inputs.phase_biases);
    } else {
      d.load_notes.push_back("ambiguity resolution: no phase biases given: float");
    }
  }
}

PppPipeline::~PppPipeline() = default;

const ProductAssembly* PppPipeline::productAssembly() const {
  return impl_->assembly ? &*impl_->assembly : nullptr;
}

const RinexObsHeader& PppPipeline::header() const { return impl_->source->header(); }

std::string PppPipeline::stationName() const {
  std::string name = impl_->source->header().marker_name;
  if (name.empty()) name = fileBaseName(impl_->source->name());
  name = name.substr(0, std::min<std::size_t>(4, name.size()));
  for (auto& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return name;
}

std::optional<int> PppPipeline::glonassChannel(const SatelliteId& sat) const {
  return channelsHeaderFirst(header().glonass_channels, config_.signals.glonass_channels).channel(sat.prn);
}

std::vector<std::string> PppPipeline::notes() const {
  std::vector<std::string> n = impl_->load_notes;
  for (const auto& s : impl_->processor->antennaSources()) n.push_back("antenna " + s);
  for (const auto& w : impl_->processor->receiverAntennaWarnings()) n.push_back("warning: " + w);
  for (const auto& w : impl_->processor->satelliteReferenceNotes()) n.push_back("warning: " + w);
  return n;
}

void PppPipeline::setImu(std::vector<ImuSample> readings) {
  std::stable_sort(readings.begin(), readings.end(),
                   [](const ImuSample& a, const ImuSample& b) { return a.time - b.time < 0.0; });
  imu_ = std::move(readings);
  impl_->processor->setImu(&imu_);
}

const std::vector<std::string>& PppPipeline::receiverAntennaWarnings() const {
  return impl_->processor->receiverAntennaWarnings();
}

double PppPipeline::progress() const { return impl_->source->progress(); }

void PppPipeline::adoptEstimatorSystems(const PppEstimator& estimator) {
  // The estimator's state holds one clock per system: an estimator made from
  // another configuration than config() (e.g. the caller's, before the products
  // named the systems) processes its own systems, said in the notes.
  const std::vector<GnssSystem> systems = estimator.layout().clockSystems();
  if (systems == config_.signals.systems) return;
  std::string names;
  for (auto s : systems) names += (names.empty() ? "" : ", ") + std::string(systemName(s));
  impl_->load_notes.push_back("systems: " + names + " (those of the estimator's state)");
  config_.signals.systems = systems;
  impl_->start(config_);
}

/// What a run collects over its epochs for the summary's problems and notes.
struct PppPipeline::RunTally {
  /// Code-reference notes merged over epochs: text -> union of the satellites.
  std::map<std::string, std::set<std::string>> code_notes;
  ResidualSummary residuals;
  /// Satellites rejected, for naming those an input problem took out of the run.
  std::map<SatelliteId, std::pair<std::size_t, std::string>> rejected_epochs;  // count, first reason
  std::optional<GnssTime> first_solved;  // for the time to first fix

  void mergeSelectionNotes(const std::vector<SignalSelectionNote>& notes) {
    for (const SignalSelectionNote& n : notes) {
      std::set<std::string>& sats = code_notes[n.text];
      for (const SatelliteId& sat : n.satellites) sats.insert(sat.toString());
    }
  }
};

PppRunSummary PppPipeline::run(PppEstimator& estimator, const EpochCallback& on_epoch) {
  PppRunSummary summary;
  summary.estimator = estimator.name();
  // 1. The observation file is streamed once.
  if (impl_->ran) {
    summary.problems.push_back("the pipeline has already run (the observation file is streamed once)");
    return summary;
  }
  impl_->ran = true;
  // 2. The estimator's systems, the load problems and the starting point.
  startRun(estimator, summary);
  const auto wall_start = std::chrono::steady_clock::now();
  // 3. Every epoch through the processor and the estimator, counted.
  RunTally tally;
  processEpochs(estimator, on_epoch, summary, tally);
  // 4. Arcs still open at the end of the data.
  estimator.arcsEnded(impl_->processor->finish());
  // 5. Input problems, and the satellites they took out of the run.
  reportInputProblems(tally, summary);
  // 6. Residual statistics and notes.
  finishNotes(tally, summary);
  summary.processing_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return summary;
}

void PppPipeline::startRun(PppEstimator& estimator, PppRunSummary& summary) {
  adoptEstimatorSystems(estimator);
  summary.problems = impl_->load_problems;
  const RinexObsHeader& header = impl_->source->header();
  if (header.approx_position_ecef_m && header.approx_position_ecef_m->norm() > 1e6)
    estimator.setApproximatePosition(*header.approx_position_ecef_m);
}

bool PppPipeline::readEpoch(ObsEpoch& epoch) {
  ObservationSource& source = *impl_->source;
  const ObservationRead read = source.next(epoch);
  if (read == ObservationRead::End) return false;
  if (read == ObservationRead::Error) {
    const ObservationProblem e = source.error().value_or(ObservationProblem{source.name(), 0, "read error"});
    throw ParseError(e.file, e.line, e.reason);
  }
  return true;
}

void PppPipeline::processEpochs(PppEstimator& estimator, const EpochCallback& on_epoch, PppRunSummary& summary,
                                RunTally& tally) {
  PppEpochProcessor& processor = *impl_->processor;
  ObsEpoch epoch;
  PppEpochRecord rec;
  std::vector<SignalSelectionNote> selection_notes;
  while (readEpoch(epoch)) {
    ++summary.epochs_read;
    rec = processor.process(epoch, estimator, &selection_notes);
    if (rec.refused) {
      ++summary.epochs_refused;
      summary.problems.push_back("epoch " + epoch.time.toString() + " refused: " + rec.reason);
      if (on_epoch) on_epoch(rec);
      continue;
    }
    if (rec.gap_s) ++summary.data_gaps;
    tally.mergeSelectionNotes(selection_notes);
    countEpoch(rec, summary, tally);
    if (on_epoch) on_epoch(rec);
  }
}

void PppPipeline::countEpoch(const PppEpochRecord& rec, PppRunSummary& summary, RunTally& tally) {
  summary.arcs += static_cast<std::size_t>(rec.new_arcs);
  summary.slips += static_cast<std::size_t>(rec.slips);
  summary.slips_repaired += rec.slip_repairs.size();
  summary.slip_repairs_refused += static_cast<std::size_t>(rec.slip_repairs_refused);
  switch (rec.status) {
    case EpochStatus::Ok:
      ++summary.epochs_solved;
      if (!tally.first_solved) tally.first_solved = rec.solution.time;
      if (rec.solution.status == SolutionStatus::PppFixed) {
        ++summary.epochs_fixed;
        if (!summary.time_to_first_fix_s) summary.time_to_first_fix_s = rec.solution.time - *tally.first_solved;
      }
      break;
    case EpochStatus::NoSolution: ++summary.epochs_no_solution; break;
    case EpochStatus::Failed: ++summary.epochs_failed; break;
  }
  tally.residuals.add(rec);
  for (const auto& x : rec.rejected) summary.rejection_counts[{x.stage, x.reason}]++;
  for (const auto& x : rec.rejected) {
    auto& r = tally.rejected_epochs[x.satellite];
    if (r.first++ == 0) r.second = x.text();
  }
  if (rec.status != EpochStatus::Ok) summary.no_solution_counts[rec.no_solution_reason]++;
  if (rec.estimator_reset) ++summary.estimator_resets;
  if (rec.solution.integrity == SolutionIntegrity::Inconsistent) ++summary.epochs_inconsistent;
}

void PppPipeline::reportInputProblems(const RunTally& tally, PppRunSummary& summary) const {
  for (const auto& p : impl_->source->problems())
    summary.problems.push_back(p.file + " line " + std::to_string(p.line) + ": " + p.reason);
  if (summary.problems.empty()) return;
  // With input problems, name the satellites the run never used.
  std::string dropped;
  for (const auto& [sat, r] : tally.rejected_epochs) {
    if (tally.residuals.used(sat)) continue;
    dropped += (dropped.empty() ? "" : "; ") + sat.toString() + " (" + std::to_string(r.first) +
               " epoch(s), first: " + r.second + ")";
  }
  if (!dropped.empty()) summary.problems.push_back("satellites never used: " + dropped);
}

void PppPipeline::finishNotes(const RunTally& tally, PppRunSummary& summary) const {
  const Impl& d = *impl_;
  summary.residual_statistics = tally.residuals.statistics();
  summary.notes = notes();
  const RinexObsHeader& header = d.source->header();
  const std::vector<std::string> suspects =
      tally.residuals.suspectChannelNotes(channelsHeaderFirst(header.glonass_channels, config_.signals.glonass_channels));
  summary.notes.insert(summary.notes.end(), suspects.begin(), suspects.end());
  for (const auto& [text, sats] : tally.code_notes) {
    std::string note = "code reference: " + text;
    if (!sats.empty()) note += ":";
    for (const auto& sat : sats) note += " " + sat;
    summary.notes.push_back(note);
  }
  if (tally.code_notes.empty() && d.products.biases)
    summary.notes.push_back("code reference: codes aligned to the clock reference by the OSB of " +
                            d.bias_file_name.value_or(d.products.biases->describeSource()));
}

}  // namespace ppp
