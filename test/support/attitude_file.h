#pragma once
// The attitude file of ppp_solve's GNSS/INS estimators (<stem>_attitude.csv,
// ppp_solve_run.cpp) read back for the tests: its header and each row's cells.
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace ppp::test {

struct AttitudeRow {
  std::string line;                // as written
  std::vector<std::string> cells;  // split at the commas (empty cells kept, the last ones too)
};

struct AttitudeFileRows {
  std::string header;
  std::vector<AttitudeRow> rows;
};

/// The file's header and rows; nullopt when it cannot be opened.
inline std::optional<AttitudeFileRows> readAttitudeFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  AttitudeFileRows file;
  std::getline(in, file.header);
  std::string line;
  while (std::getline(in, line)) {
    AttitudeRow row;
    row.line = line;
    std::size_t from = 0;  // every cell, the empty last ones too
    for (std::size_t comma = line.find(','); comma != std::string::npos; comma = line.find(',', from)) {
      row.cells.push_back(line.substr(from, comma - from));
      from = comma + 1;
    }
    row.cells.push_back(line.substr(from));
    file.rows.push_back(std::move(row));
  }
  return file;
}

}  // namespace ppp::test
