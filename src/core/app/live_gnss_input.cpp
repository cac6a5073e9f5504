#include "ppp_bayes_tree/app/live_gnss_input.h"

#include "ppp_bayes_tree/models/broadcast_ephemeris_store.h"

namespace ppp {

std::string_view liveProductModeName(LiveProductMode mode) {
  switch (mode) {
    case LiveProductMode::PreciseSsr: return "precise SSR";
    case LiveProductMode::BroadcastOnly: return "broadcast only";
  }
  return "unknown";
}

std::string_view streamStallName(StreamStall stall) {
  switch (stall) {
    case StreamStall::Ok: return "ok";
    case StreamStall::Warn: return "warn";
    case StreamStall::Error: return "error";
  }
  return "unknown";
}

struct LiveGnssInput::Impl {
  LiveInputOptions options;
  BroadcastEphemerisStore broadcast;
  RinexObsHeader header;
  SsrCorrectionStore store;
};

LiveGnssInput::LiveGnssInput(LiveInputOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
}
LiveGnssInput::~LiveGnssInput() = default;
void LiveGnssInput::feed(const StreamChunk&) {}
std::vector<LiveReadyEpoch> LiveGnssInput::takeReadyEpochs(std::optional<double>) { return {}; }
std::vector<LiveReadyEpoch> LiveGnssInput::finish() { return {}; }
const EphemerisSource& LiveGnssInput::ephemeris() const { return impl_->broadcast; }
const BiasProvider* LiveGnssInput::biases() const { return nullptr; }
const RinexObsHeader& LiveGnssInput::header() const { return impl_->header; }
bool LiveGnssInput::takeHeaderChanged() { return false; }
std::vector<LiveStreamStatus> LiveGnssInput::streams() const { return {}; }
LiveProductMode LiveGnssInput::mode() const { return LiveProductMode::PreciseSsr; }
std::uint64_t LiveGnssInput::releasedEpochs(LiveProductMode) const { return 0; }
std::uint64_t LiveGnssInput::satellitesWithoutEphemeris() const { return 0; }
std::size_t LiveGnssInput::navigationRecords() const { return 0; }
const SsrCorrectionStore& LiveGnssInput::corrections() const { return impl_->store; }

}  // namespace ppp
