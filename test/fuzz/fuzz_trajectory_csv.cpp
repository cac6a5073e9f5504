#include "trajectory_csv_fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* d, size_t n) {
  ppp::fuzz::fuzzTrajectoryCsv(d, n);
  return 0;
}
