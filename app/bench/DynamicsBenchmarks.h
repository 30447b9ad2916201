// SPDX-License-Identifier: Apache-2.0
#pragma once
// Benchmarks of the engine: steps per second of each integrator on a block of about 5,300
// springs (the paper's liver size) and of about 100,000, and the cost of building the mesh.
// Issue targets on the 2-core machine: 5,300 springs at 5,000 steps/s explicit and 1,000
// steps/s implicit; 100,000 springs at 200 steps/s.

#include <string>

namespace tissuesim::app {

void registerDynamicsBenchmarks(const std::string& tissuePath);

}  // namespace tissuesim::app
