// SPDX-License-Identifier: Apache-2.0
#pragma once
// The FEM at its own rate's update against the time its scene gives it (physics.
// fem_update_latency_ms): the liver poke (1 to 5 mm at 2 mm/s, as `organ-poke` drives it) through
// the bundled refined FEM scene, weightless on its 4 mm body, and through the same scene refined
// to 2.5 mm under the default scene's gravity and on its tray, and to 2 mm growing 1 mm per mm
// there, the body within 10 % of the weighted reference at every depth: the bodies whose update
// decides whether an FEM scene can be the default (docs/performance-details.md, "The update's
// time, and the compliance and the elements on two threads", "Under gravity within 10 % at every
// depth, given the update's time"). Counters: the updates' mean wall time
// (update_ms) against the scene's latency (latency_ms), the updates taken, the body's quadratic
// nodes.

namespace tissuesim::app {

void registerFemUpdateBenchmarks();

}  // namespace tissuesim::app
