#include "ppp_bayes_tree/io/rinex/observation_source.h"

#include <algorithm>
#include <fstream>

#include "ppp_bayes_tree/io/line_source.h"
#include "ppp_bayes_tree/io/parse_error.h"
#include "ppp_bayes_tree/io/rinex/rinex_obs_reader.h"

namespace ppp {

RinexObservationSource::RinexObservationSource(const std::string& path)
    : path_(path),
      name_(fileBaseName(path)),
      reader_(std::make_unique<RinexObsReader>(RinexObsReader::open(path))) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  size_bytes_ = in ? static_cast<std::size_t>(std::max<std::streamoff>(0, in.tellg())) : 0;
}

RinexObservationSource::~RinexObservationSource() = default;

const RinexObsHeader& RinexObservationSource::header() const { return reader_->header(); }

ObservationRead RinexObservationSource::next(ObsEpoch& epoch) {
  if (error_) return ObservationRead::Error;
  try {
    return reader_->next(epoch) ? ObservationRead::Epoch : ObservationRead::End;
  } catch (const ParseError& e) {
    error_ = ObservationProblem{e.file().empty() ? name_ : fileBaseName(e.file()), e.line(), e.reason()};
  } catch (const std::exception& e) {
    error_ = ObservationProblem{name_, 0, e.what()};
  }
  return ObservationRead::Error;
}

std::vector<ObservationProblem> RinexObservationSource::problems() const {
  std::vector<ObservationProblem> out;
  for (const auto& p : reader_->report().problems()) out.push_back({name_, p.line, p.reason});
  return out;
}

double RinexObservationSource::progress() const {
  if (size_bytes_ == 0) return 0.0;
  return std::min(1.0, static_cast<double>(reader_->source().bytesRead()) / static_cast<double>(size_bytes_));
}

}  // namespace ppp
