// SPDX-License-Identifier: Apache-2.0
#pragma once
// Wall-clock seconds since a start, for the experiments' reports.

#include <chrono>

namespace tissuesim {

inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace tissuesim
