#pragma once
// ObservationSource: where the processing chain gets its observation epochs,
// one at a time and in the order received, with the header that describes them
// (observation types, receiver antenna, GLONASS channels). A RINEX/CRX file
// (RinexObservationSource), epochs held in memory (InMemoryObservationSource:
// a simulated flight, a test), later a decoded receiver stream (RTCM, UBX).
//
// next() says which of three things happened: an epoch, the end of the data,
// or an error that ends the data (error(): file, line and reason). Records that
// were skipped without ending the data are listed by problems().
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/rinex/rinex_obs_header.h"
#include "ppp_bayes_tree/types/obs_epoch.h"

namespace ppp {

class RinexObsReader;

enum class ObservationRead { Epoch, End, Error };

/// A problem of the observation data: where (file and line, 0 = not tied to a
/// line) and why.
struct ObservationProblem {
  std::string file;
  std::size_t line = 0;
  std::string reason;
};

class ObservationSource {
 public:
  virtual ~ObservationSource() = default;
  virtual const RinexObsHeader& header() const = 0;
  /// The next epoch into `epoch`, or End, or Error (then error() says why).
  virtual ObservationRead next(ObsEpoch& epoch) = 0;
  /// The error that ended the data (set after next() returned Error).
  virtual std::optional<ObservationProblem> error() const = 0;
  /// Records skipped so far (malformed, not fatal).
  virtual std::vector<ObservationProblem> problems() const { return {}; }
  /// Fraction consumed (0..1), for progress bars.
  virtual double progress() const = 0;
  /// The name the data is reported under (file name, "in-memory", a topic).
  virtual std::string name() const = 0;
};

/// A RINEX 2/3/4 or Hatanaka (CRX, plain or gzip) observation file, streamed.
class RinexObservationSource : public ObservationSource {
 public:
  /// Opens the file and reads its header (throws FileOpenError / ParseError).
  explicit RinexObservationSource(const std::string& path);
  ~RinexObservationSource() override;

  const RinexObsHeader& header() const override;
  ObservationRead next(ObsEpoch& epoch) override;
  std::optional<ObservationProblem> error() const override { return error_; }
  std::vector<ObservationProblem> problems() const override;
  double progress() const override;
  std::string name() const override { return name_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_, name_;
  std::unique_ptr<RinexObsReader> reader_;
  std::size_t size_bytes_ = 0;
  std::optional<ObservationProblem> error_;
};

/// Epochs held by the caller (must outlive the source), served in order.
class InMemoryObservationSource : public ObservationSource {
 public:
  InMemoryObservationSource(const RinexObsHeader& header, const std::vector<ObsEpoch>& epochs,
                            std::string name = "in-memory")
      : header_(header), epochs_(epochs), name_(std::move(name)) {}

  const RinexObsHeader& header() const override { return header_; }
  ObservationRead next(ObsEpoch& epoch) override {
    if (next_ >= epochs_.size()) return ObservationRead::End;
    epoch = epochs_[next_++];
    return ObservationRead::Epoch;
  }
  std::optional<ObservationProblem> error() const override { return std::nullopt; }
  double progress() const override {
    return epochs_.empty() ? 1.0 : static_cast<double>(next_) / static_cast<double>(epochs_.size());
  }
  std::string name() const override { return name_; }

 private:
  const RinexObsHeader& header_;
  const std::vector<ObsEpoch>& epochs_;
  std::string name_;
  std::size_t next_ = 0;
};

}  // namespace ppp
