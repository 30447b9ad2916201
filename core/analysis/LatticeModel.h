// SPDX-License-Identifier: Apache-2.0
#pragma once
// What carries a lattice's elasticity in the virtual experiments: its springs, or the tissue's
// isochoric energy in each tet with the volume term per cube as its volumetric part
// (fem/TetIsochoricForceField.h; a scene's effects.model fem).

namespace tissuesim {

enum class LatticeModel { Springs, IsochoricTets };

}  // namespace tissuesim
