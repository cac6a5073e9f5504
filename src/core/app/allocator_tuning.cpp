#include "ppp_bayes_tree/app/allocator_tuning.h"

#include <cstdlib>  // defines __GLIBC__ with the GNU C library

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace ppp {

bool useAllocatorWithoutFastBins() {
#if defined(__GLIBC__)
  return mallopt(M_MXFAST, 0) == 1;
#else
  return false;
#endif
}

}  // namespace ppp
