#include "rinex_nav_fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* d, size_t n) { ppp::fuzz::fuzzRinexNav(d, n); return 0; }
