#include "ppp_bayes_tree/io/products/product_antenna_model.h"

#include "ppp_bayes_tree/io/fixed_width.h"
#include "ppp_bayes_tree/io/line_source.h"

namespace ppp {

std::string productAntennaModel(const std::string& path) {
  auto src = openLineSource(path);
  std::string line;
  // SP3 comments precede the first epoch line ("*  yyyy ..."); a clock header ends
  // with END OF HEADER. Both are short: stop after 1000 lines in any case.
  for (int n = 0; n < 1000 && src->next(line); ++n) {
    if (line.rfind("/*", 0) == 0) {
      const auto p = line.find("PCV:");
      if (p != std::string::npos) {
        const auto e = line.find_first_of(" \t", p + 4);
        return line.substr(p + 4, e == std::string::npos ? std::string::npos : e - (p + 4));
      }
      continue;
    }
    if (line.size() > 1 && line[0] == '*' && line[1] == ' ') break;  // SP3 data begin
    if (line.size() >= 60) {
      const std::string_view label = trim(column(line, 60, 20));
      if (label == "SYS / PCVS APPLIED") {
        std::string name(trim(column(line, 20, 40)));
        const auto dot = name.find_last_of('.');
        if (dot != std::string::npos) name = name.substr(0, dot);
        if (!name.empty()) return name;
      } else if (label == "END OF HEADER") {
        break;
      }
    }
  }
  return "";
}

}  // namespace ppp
