// SPDX-License-Identifier: Apache-2.0
#include "numerics/CpuFeatures.h"

namespace tissuesim {

bool hasAvxAndFma() {
#if defined(__x86_64__)
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx") && __builtin_cpu_supports("fma");
  }();
  return has;
#else
  return false;
#endif
}

}  // namespace tissuesim
