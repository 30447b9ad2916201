// SPDX-License-Identifier: Apache-2.0
#pragma once
// A trainee's session, at random and reproducibly (one seed, one session): the soak test's
// workload. Over `duration_s` the tool repeats
//   transit high above the organ -> descend to 1 cm above a random point of its upper drawn
//   surface (outward normal within 60 degrees of up, not held by the scene) -> press along a
//   shaft tilted up to 30 degrees off vertical, 0-5 cm past the surface at 2 cm/s-1.5 m/s ->
//   in one cycle of three, close the grasper at the deepest point, lift 1 cm, release ->
//   withdraw at the same speed -> rest 0-0.5 s
// so it pokes deep and fast, grasps, releases and leaves the tissue to recover, as hands do.
// Between cycles the tool travels 5 cm above the organ's highest point, at 0.5 m/s, so a
// transit never drags it through the tissue. Positions in m, times in s.

#include <cstdint>

#include "sim/InstrumentScript.h"
#include "sim/Simulation.h"

namespace tissuesim {

/// @throws std::invalid_argument when the scene has no instrument, or no upper surface to poke.
InstrumentScript randomSession(const Simulation& simulation, double duration_s, std::uint64_t seed);

}  // namespace tissuesim
