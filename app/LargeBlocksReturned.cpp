// SPDX-License-Identifier: Apache-2.0
#include "app/LargeBlocksReturned.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace tissuesim::app {

void returnLargeBlocksToTheSystem() {
#if defined(__GLIBC__)
  constexpr int kMappedFrom_bytes = 512 * 1024;
  constexpr int kTrimmedFrom_bytes = 1024 * 1024;
  mallopt(M_MMAP_THRESHOLD, kMappedFrom_bytes);
  mallopt(M_TRIM_THRESHOLD, kTrimmedFrom_bytes);
#endif
}

}  // namespace tissuesim::app
