// ppp_pos_stats: position error statistics of RTKLIB-style .pos files (xyz or
// llh, week/tow or calendar time) against a truth point, printed as a table;
// several files are printed side by side, e.g. RTKLIB's and ours.
//
// usage: ppp_pos_stats FILE.pos [FILE2.pos ...] --truth X,Y,Z [--labels A,B,...]
//                      [--first-minutes 15] [--tail-minutes 30] [--json OUT.json]
// With --json, the statistics of the first file are also written as JSON.
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "ppp_bayes_tree/evaluation/position_error_statistics.h"
#include "ppp_bayes_tree/evaluation/rtklib_pos.h"
#include "ppp_bayes_tree/io/parse_error.h"

namespace {

std::vector<std::string> splitComma(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

int usage(const std::string& why) {
  std::cerr << "ppp_pos_stats: " << why << "\n"
            << "usage: ppp_pos_stats FILE.pos [FILE2.pos ...] --truth X,Y,Z [--labels A,B,...]\n"
            << "                     [--first-minutes 15] [--tail-minutes 30] [--json OUT.json]\n";
  return 2;
}

bool parseNumber(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files, labels;
  std::optional<Eigen::Vector3d> truth;
  std::string json_path;
  ppp::StatisticsOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string { return i + 1 < argc ? argv[++i] : std::string(); };
    double v = 0.0;
    if (a == "--truth") {
      const auto parts = splitComma(value());
      Eigen::Vector3d t;
      if (parts.size() != 3) return usage("--truth needs X,Y,Z");
      for (int k = 0; k < 3; ++k)
        if (!parseNumber(parts[k], t(k))) return usage("bad --truth value '" + parts[k] + "'");
      truth = t;
    } else if (a == "--labels") {
      labels = splitComma(value());
    } else if (a == "--first-minutes") {
      if (!parseNumber(value(), v) || v <= 0) return usage("bad --first-minutes");
      options.convergence_window_s = v * 60.0;
    } else if (a == "--tail-minutes") {
      if (!parseNumber(value(), v) || v <= 0) return usage("bad --tail-minutes");
      options.tail_window_s = v * 60.0;
    } else if (a == "--json") {
      json_path = value();
    } else if (a == "-h" || a == "--help") {
      return usage("help");
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option " + a);
    } else {
      files.push_back(a);
    }
  }
  if (files.empty()) return usage("no .pos file given");
  if (!truth) return usage("--truth X,Y,Z is required");

  std::vector<std::pair<std::string, ppp::PositionErrorStatistics>> columns;
  for (std::size_t i = 0; i < files.size(); ++i) {
    try {
      const auto pos = ppp::readRtklibPos(files[i]);
      if (!pos.report.clean()) std::cerr << pos.report.summary() << "\n";
      const std::string label = i < labels.size() ? labels[i] : files[i].substr(files[i].find_last_of('/') + 1);
      columns.emplace_back(label, ppp::computePositionErrorStatistics(ppp::toSolutionEpochs(pos), *truth, options));
    } catch (const ppp::FileOpenError& e) {
      std::cerr << "ppp_pos_stats: " << e.what() << "\n";
      return 1;
    }
  }
  std::cout << ppp::formatStatisticsComparison(columns);
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << ppp::statisticsToJson(columns.front().second, columns.front().first);
    if (!out) {
      std::cerr << "ppp_pos_stats: cannot write " << json_path << "\n";
      return 1;
    }
  }
  return 0;
}
