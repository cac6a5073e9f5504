#include "sp3_fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* d, size_t n) { ppp::fuzz::fuzzSp3(d, n); return 0; }
