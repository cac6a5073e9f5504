// ppp_inspect FILE...
//
// Prints, per file: type, version and span; interval and epoch count; satellites
// per system and signals; the problems found. Given observations together with
// orbit/clock products, also says whether the products cover the observations
// and which observed satellites they miss.
#include <cstdio>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/file_summary.h"
#include "ppp_bayes_tree/io/transport/file_type.h"
#include "ppp_bayes_tree/io/transport/untrusted_text.h"
#include "ppp_bayes_tree/app/inspection.h"

namespace {

void printUsage() {
  std::fprintf(stderr,
               "usage: ppp_inspect FILE...\n"
               "  Summarises GNSS files (RINEX obs 2/3/4 and Hatanaka CRX, RINEX nav, SP3, RINEX clock,\n"
               "  ANTEX, Bias-SINEX, BLQ; plain or gzip) and, given observations with SP3/CLK products,\n"
               "  checks that the products cover the observations.\n"
               "  No file given: try ./scripts/demo.sh, which inspects the ZIM2 dataset in ../shared/data.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    printUsage();
    return 2;
  }
  const std::vector<std::string> paths(argv + 1, argv + argc);
  int failures = 0;
  ppp::Inspection inspection;
  for (const auto& path : paths) {
    try {
      const ppp::FileSummary summary = inspection.add(path);
      std::fputs(ppp::formatSummary(summary).c_str(), stdout);
    } catch (const std::exception& e) {
      ++failures;
      const std::string why = ppp::printableText(e.what(), std::numeric_limits<std::size_t>::max());
      std::printf("== %s\n  ERROR: %s\n\n", path.c_str(), why.c_str());
    }
  }
  std::fputs(inspection.coverageReport().c_str(), stdout);
  return failures == 0 ? 0 : 1;
}
