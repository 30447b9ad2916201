// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

namespace tissuesim::app {

/// Frame time of the bundled scene (offscreen; llvmpipe under Xvfb when there is no display),
/// and the physics rate of the real-time loop alone and while frames are rendered.
void registerRenderBenchmarks(const std::string& scenePath);

}  // namespace tissuesim::app
