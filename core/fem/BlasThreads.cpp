// SPDX-License-Identifier: Apache-2.0
#include "fem/BlasThreads.h"

#include <dlfcn.h>

namespace tissuesim {

bool keepBlasToOneThread() {
  using SetThreads = void (*)(int);
  void* const symbol = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  if (symbol == nullptr) return false;
  reinterpret_cast<SetThreads>(symbol)(1);
  return true;
}

}  // namespace tissuesim
