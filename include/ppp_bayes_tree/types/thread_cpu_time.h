#pragma once
// CPU time of the calling thread, for cost figures that stay meaningful on a
// loaded machine (wall-clock time there includes waiting for a core).

#include <ctime>

namespace ppp {

/// CPU time consumed so far by the calling thread [s] (POSIX CLOCK_THREAD_CPUTIME_ID).
inline double threadCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace ppp
