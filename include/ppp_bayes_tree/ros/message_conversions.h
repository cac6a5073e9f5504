#pragma once
// Conversions between the package's ROS messages and the core types:
//   GnssObservations  <-> ObsEpoch + the receiver part of a RinexObsHeader
//   PreciseCorrections <-> CorrectionBatch (+ SatelliteBiasBatch: the biases for ambiguity resolution)
//   GNSS time          <-> week / seconds of week / time system, UTC ros::Time stamps
// Lossless for a RINEX 3 epoch: every C/L/D/S observation of a code, its LLI
// and SSI, other observation types, the epoch flag and the clock offset.
// Incoming values are checked: NaN means absent; an infinite or absurd value
// (outside the physical ranges below) excludes that observation and is
// counted with the reason; an unknown satellite or code skips that entry.
#include <map>
#include <string>

#include <ros/time.h>

#include "ppp_bayes_tree/GnssObservations.h"
#include "ppp_bayes_tree/PreciseCorrections.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/models/correction_buffer.h"
#include "ppp_bayes_tree/models/stream_bias_provider.h"
#include "ppp_bayes_tree/ppp/pipeline/product_assembly.h"
#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp_ros {

/// Message time fields of a GNSS instant, read in `system` (GPS week numbering).
struct MessageTime {
  std::uint16_t week = 0;
  double seconds_of_week = 0.0;
  std::string time_system = "GPS";
};
MessageTime toMessageTime(const ppp::GnssTime& t, ppp::TimeSystem system = ppp::TimeSystem::GPS);
/// Throws std::invalid_argument on an unknown time system or a non-finite or
/// out-of-range seconds of week. The fraction is rounded to 1 ns.
ppp::GnssTime fromMessageTime(std::uint16_t week, double seconds_of_week, const std::string& time_system);
/// UTC stamp of a GNSS instant (GPST minus the leap seconds), as ROS expects.
ros::Time utcStamp(const ppp::GnssTime& t);
/// The GNSS instant (GPST) of a UTC stamp: the inverse of utcStamp.
ppp::GnssTime fromUtcStamp(const ros::Time& stamp);

/// Counts of the problems found while converting incoming messages (reason -> count).
struct ConversionIssues {
  std::map<std::string, std::size_t> counts;
  void add(const std::string& reason) { ++counts[reason]; }
  std::size_t total() const;
};

/// ObsEpoch (+ header: types, receiver, antenna, GLONASS channels) -> message.
ppp_bayes_tree::GnssObservations toMessage(const ppp::ObsEpoch& epoch, const ppp::RinexObsHeader& header);

/// Message -> ObsEpoch. `layout` is the running header: its observation types
/// per system grow as new codes appear and its GLONASS channels as new slots
/// appear (returns true when either changed), and
/// its receiver/antenna fields are set from the message. Each satellite's slice
/// follows the layout's type list (absent: nullopt), like RinexObsReader.
/// Throws std::invalid_argument when the epoch time itself is invalid.
bool fromMessage(const ppp_bayes_tree::GnssObservations& msg, ppp::RinexObsHeader& layout, ppp::ObsEpoch& epoch,
                 ConversionIssues& issues);

ppp_bayes_tree::PreciseCorrections toMessage(const ppp::CorrectionBatch& batch);
/// Throws std::invalid_argument when the batch time is invalid.
ppp::CorrectionBatch fromMessage(const ppp_bayes_tree::PreciseCorrections& msg, ConversionIssues& issues);

/// The satellite biases for integer ambiguity resolution into a batch message:
/// ar_bias_source and satellites[].biases of the satellites the message carries
/// (a satellite without corrections gets none).
void addBiases(ppp_bayes_tree::PreciseCorrections& msg, const ppp::SatelliteBiasBatch& biases);
/// The message's satellites[].biases (empty without ar_bias_source). An unknown
/// satellite or observable code, or a non-finite or absurd value (|bias| >= 1000 m),
/// skips that bias, counted with the reason. Throws std::invalid_argument when the
/// batch time is invalid.
ppp::SatelliteBiasBatch biasesFromMessage(const ppp_bayes_tree::PreciseCorrections& msg, ConversionIssues& issues);
/// What a correction stream declares about its products, from its first batch
/// (message and converted batch): the systems it carries, the analysis centre of
/// its clocks (clock_source) and its satellite antenna model (for the product
/// assembly's satellite antennas and PPP-AR gate).
ppp::StreamedProductInfo streamedProductInfo(const ppp_bayes_tree::PreciseCorrections& msg,
                                             const ppp::CorrectionBatch& batch);
/// PreciseCorrections.ar_bias_kind <-> the product assembly's phase information (unknown values: None).
ppp::PhaseInformation phaseInformation(std::uint8_t ar_bias_kind);
std::uint8_t arBiasKind(ppp::PhaseInformation phase);

}  // namespace ppp_ros
