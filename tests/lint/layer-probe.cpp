// SPDX-License-Identifier: Apache-2.0
// Compiled as part of the springs layer by tests/lint/check-layers.sh, which expects it to fail:
// a layer cannot include a header of a layer above it (core/CMakeLists.txt). The order matters:
// the first header missing stops the compiler.
// clang-format off
#include "springs/SpringMesh.h"  // its own layer: found
#include "sim/Simulation.h"      // a layer above: must not be found
// clang-format on
