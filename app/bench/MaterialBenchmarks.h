// SPDX-License-Identifier: Apache-2.0
#pragma once
// Benchmarks of the material layer: table precompute (the paper's initialisation took
// 1,522 ms; the target is under 5 ms) and per-spring table lookups.

#include <string>

namespace tissuesim::app {

/// Registers the material benchmarks for the tissue in `tissuePath`.
void registerMaterialBenchmarks(const std::string& tissuePath);

}  // namespace tissuesim::app
