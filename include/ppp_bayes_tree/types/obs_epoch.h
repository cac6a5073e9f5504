#pragma once
// ObsEpoch: one observation epoch, as read from a RINEX observation file,
// decoded from an RTCM or UBX stream, or simulated.
//
// Built for speed: all observations of the epoch live in one flat vector and
// each satellite refers to a slice of it, so a reader that refills the same
// ObsEpoch performs no heap allocation once the vectors have grown. Within a
// satellite's slice, observation k has the k-th code of the header's type list
// of that system (RinexObsHeader::types(system)).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ppp_bayes_tree/types/gnss_time.h"
#include "ppp_bayes_tree/types/observation_code.h"
#include "ppp_bayes_tree/types/satellite_id.h"

namespace ppp {

struct Observation {
  ObservationCode code;
  std::optional<double> value;       // blank field -> nullopt (m, cycles, Hz, dB-Hz...)
  std::optional<std::uint8_t> lli;   // loss-of-lock indicator 0..9, blank -> nullopt
  std::optional<std::uint8_t> ssi;   // signal strength indicator 0..9, blank -> nullopt
};

/// RINEX epoch flags (RINEX 3.05 table A3).
enum class EpochFlag : std::uint8_t {
  Ok = 0,
  PowerFailure = 1,      // power failure between the previous and this epoch
  StartMoving = 2,       // special records: the reader skips and counts them
  NewSiteOccupation = 3,
  HeaderInformation = 4,
  ExternalEvent = 5,
  CycleSlipRecords = 6,  // the records list cycle slips, not regular observations
};

struct SatelliteObservations {
  SatelliteId satellite;
  std::uint32_t first = 0;  // index of the first observation in ObsEpoch::observations
  std::uint32_t count = 0;  // number of observations (the system's type count)
};

struct ObsEpoch {
  GnssTime time;  // GPST instant of the time tag (converted from the file's time system)
  EpochFlag flag = EpochFlag::Ok;
  std::optional<double> receiver_clock_offset_s;
  std::vector<SatelliteObservations> satellites;
  std::vector<Observation> observations;
  std::size_t line = 0;  // line number of the epoch line

  bool powerFailure() const { return flag == EpochFlag::PowerFailure; }
  bool cycleSlipRecords() const { return flag == EpochFlag::CycleSlipRecords; }

  /// Pointer to the first observation of satellite i (count: satellites[i].count).
  const Observation* begin(std::size_t i) const {
    return observations.data() + satellites[i].first;
  }
  const Observation* end(std::size_t i) const { return begin(i) + satellites[i].count; }
  /// The observation of a satellite and code, nullptr when absent (linear search).
  const Observation* find(const SatelliteId& satellite, const ObservationCode& code) const;
  /// Index of a satellite in `satellites`, nullopt when absent.
  std::optional<std::size_t> indexOf(const SatelliteId& satellite) const;

  void clear() {
    satellites.clear();
    observations.clear();
    receiver_clock_offset_s.reset();
    flag = EpochFlag::Ok;
  }
};

}  // namespace ppp
