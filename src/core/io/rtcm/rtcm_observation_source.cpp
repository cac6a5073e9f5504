#include "ppp_bayes_tree/io/rtcm/rtcm_observation_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/epoch_time_screen.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rtcm/rtcm_ssr_decoder.h"
#include "ppp_bayes_tree/io/stream_pump.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// SSR frames in the observation stream (a caster stream carrying corrections
/// too, as ppp_stream_make writes) belong to the correction input (--ssr): left
/// alone here, not counted as unknown messages.
bool isCorrectionFrame(const Rtcm3Frame& frame) { return RtcmSsrDecoder::isSsrMessageType(frame.message_type); }

constexpr std::size_t kMinWeekEvidenceRecords = 3;

EpochOrigin epochOrigin(const StreamEpoch& e) { return EpochOrigin{e.byte_offset, e.frame_index, 0}; }

std::unique_ptr<std::FILE, int (*)(std::FILE*)> openBinary(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw FileOpenError("cannot open RTCM 3 file " + path);
  return f;
}

}  // namespace

std::optional<std::string> referenceDateContradiction(const GnssTime& reference, const GnssTime& first,
                                                      const GnssTime& last, const BroadcastWeekEvidence& evidence) {
  // Most ephemerides counted must disagree (a few stale or odd records do not decide).
  if (evidence.records < kMinWeekEvidenceRecords || 2 * evidence.disagreement_s.size() <= evidence.records)
    return std::nullopt;
  std::vector<double> off = evidence.disagreement_s;
  std::nth_element(off.begin(), off.begin() + static_cast<std::ptrdiff_t>(off.size() / 2), off.end());
  const double median_s = off[off.size() / 2];
  const CalendarTime given = reference.toCalendar(TimeSystem::GPS);
  const CalendarTime stream = (first + median_s).toCalendar(TimeSystem::GPS);
  return format("the reference date %04d/%02d/%02d (--ref-date) places the epochs at %s to %s, but %zu of the "
                "stream's %zu ephemerides (GPS/QZSS, Galileo, BeiDou; their weeks as broadcast) have their "
                "reference time %.1f days %s (median): the date is wrong, the stream says about %04d/%02d/%02d "
                "(without --ref-date, Galileo/BeiDou ephemerides place the epochs)",
                given.year, given.month, given.day, first.toString(TimeSystem::GPS, 0).c_str(),
                last.toString(TimeSystem::GPS, 0).c_str(), evidence.disagreement_s.size(), evidence.records,
                std::fabs(median_s) / 86400.0, median_s < 0.0 ? "earlier" : "later", stream.year, stream.month,
                stream.day);
}

void fillStationHeader(const RtcmStationInfo& station, RinexObsHeader& header) {
  if (station.station_id) {
    header.marker_name = format("%04d", *station.station_id);
  }
  header.receiver_type = station.receiver_type;
  header.receiver_version = station.receiver_firmware;
  header.receiver_number = station.receiver_serial;
  header.antenna_number = station.antenna_serial;
  // The RTCM antenna descriptor is the IGS name: model in columns 1-16, radome 17-20.
  const std::string& d = station.antenna_descriptor;
  auto trim = [](std::string s) {
    while (!s.empty() && s.back() == ' ') s.pop_back();
    std::size_t b = 0;
    while (b < s.size() && s[b] == ' ') ++b;
    return s.substr(b);
  };
  header.antenna_type = trim(d.substr(0, std::min<std::size_t>(16, d.size())));
  header.antenna_radome = d.size() > 16 ? trim(d.substr(16)) : std::string();
  if (station.arp_ecef_m) header.approx_position_ecef_m = *station.arp_ecef_m;
  header.antenna_delta_hen_m = Eigen::Vector3d(station.antenna_height_m.value_or(0.0), 0.0, 0.0);
}

RtcmObservationSource::RtcmObservationSource(const std::string& path, Rtcm3DecoderOptions options)
    : path_(path), name_(fileBaseName(path)), options_(std::move(options)) {
  // Scan.
  auto f = openBinary(path);
  Rtcm3Decoder scan(options_);
  scan.setForeignFrameHandler(isCorrectionFrame);
  StreamSignalInventory inventory;
  std::optional<GnssTime> first, last;
  EpochTimeScreen<StreamEpoch> scan_screen;  // the epochs the streaming pass will serve
  auto keep = [&](const EpochTimeScreen<StreamEpoch>::Result& r) {
    for (const auto& kept : r.accepted) {
      inventory.add(kept.payload);
      if (!first || kept.time < *first) first = kept.time;
      if (!last || kept.time > *last) last = kept.time;
      ++scan_epochs_;
    }
  };
  auto drain = [&]() {
    auto& out = scan.output();
    for (const auto& e : out.epochs) keep(scan_screen.push(e.time, epochOrigin(e), e));
    out.epochs.clear();
    scan_nav_.gps.insert(scan_nav_.gps.end(), out.gps.begin(), out.gps.end());
    scan_nav_.galileo.insert(scan_nav_.galileo.end(), out.galileo.begin(), out.galileo.end());
    scan_nav_.glonass.insert(scan_nav_.glonass.end(), out.glonass.begin(), out.glonass.end());
    scan_nav_.beidou.insert(scan_nav_.beidou.end(), out.beidou.begin(), out.beidou.end());
    out.clear();
  };
  size_bytes_ = StreamPump(f.get(), path).run(
      {[&](const std::uint8_t* data, std::size_t size) { scan.feed(data, size); }, [&]() { scan.finish(); }, drain});
  keep(scan_screen.finish());
  scan_counters_ = scan.counters();
  station_ = scan.station();
  if (options_.reference_time && first && last) {
    if (const auto why = referenceDateContradiction(*options_.reference_time, *first, *last, scan.weekEvidence()))
      throw ParseError(path, 0, *why);
  }

  header_.version_text = "3.04";
  header_.version = 3.04;
  header_.major_version = 3;
  header_.file_system = 'M';
  header_.program = "ppp_bayes_tree";
  header_.comments.push_back("converted from RTCM 3: " + name_);
  fillStationHeader(station_, header_);
  inventory.fillTypes(header_);
  for (int slot = 1; slot <= GlonassChannels::kMaxSlot; ++slot) {
    if (const auto k = scan.glonassChannels().channel(slot)) header_.glonass_channels.set(slot, *k);
    else if (const auto kc = options_.glonass_channels.channel(slot)) header_.glonass_channels.set(slot, *kc);
  }
  header_.glonass_channel_entries = header_.glonass_channels.size();
  if (first) header_.time_of_first_obs = RinexHeaderTime{first->toCalendar(TimeSystem::GPS), TimeSystem::GPS, *first};
  if (last) header_.time_of_last_obs = RinexHeaderTime{last->toCalendar(TimeSystem::GPS), TimeSystem::GPS, *last};
  header_.epoch_time_system = TimeSystem::GPS;

  // Streaming pass, starting with every channel the scan found.
  Rtcm3DecoderOptions stream_options = options_;
  stream_options.glonass_channels = header_.glonass_channels;
  decoder_ = std::make_unique<Rtcm3Decoder>(stream_options);
  decoder_->setForeignFrameHandler(isCorrectionFrame);
  file_ = openBinary(path);
  pump_ = std::make_unique<StreamPump>(file_.get(), path);
}

RtcmObservationSource::~RtcmObservationSource() = default;

bool RtcmObservationSource::fill() {
  auto queue_decoded = [this]() {
    auto& out = decoder_->output();
    for (auto& e : out.epochs) {
      const GnssTime t = e.time;
      const EpochOrigin origin = epochOrigin(e);
      for (auto& kept : screen_.push(t, origin, std::move(e)).accepted) queue_.push_back(std::move(kept.payload));
    }
    if (pump_->finished())
      for (auto& kept : screen_.finish().accepted) queue_.push_back(std::move(kept.payload));
    out.clear();
  };
  const StreamPumpSteps steps{[this](const std::uint8_t* data, std::size_t size) {
                                read_bytes_ += size;
                                decoder_->feed(data, size);
                              },
                              [this]() { decoder_->finish(); }, queue_decoded};
  while (queue_next_ >= queue_.size()) {
    queue_.clear();
    queue_next_ = 0;
    if (pump_->finished()) return false;
    pump_->step(steps);
  }
  return true;
}

ObservationRead RtcmObservationSource::next(ObsEpoch& epoch) {
  if (error_) return ObservationRead::Error;
  try {
    if (!fill()) return ObservationRead::End;
  } catch (const FileOpenError& e) {  // a read error (io/stream_pump.h)
    error_ = ObservationProblem{name_, 0, e.what()};
    return ObservationRead::Error;
  }
  streamEpochToObsEpoch(queue_[queue_next_++], header_, epoch);
  return ObservationRead::Epoch;
}

std::vector<ObservationProblem> RtcmObservationSource::problems() const {
  std::vector<ObservationProblem> out;
  for (const auto& p : decoder_->counters().problems) out.push_back(ObservationProblem{path_, 0, p.describe()});
  for (const auto& p : screen_.counters().problems) out.push_back(ObservationProblem{path_, 0, p.describe()});
  return out;
}

double RtcmObservationSource::progress() const {
  return size_bytes_ == 0 ? 1.0 : static_cast<double>(read_bytes_) / static_cast<double>(size_bytes_);
}

}  // namespace ppp
