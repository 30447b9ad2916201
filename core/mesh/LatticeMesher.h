// SPDX-License-Identifier: Apache-2.0
#pragma once
// A tetrahedral mesh from a closed surface by a lattice cover: a regular grid of cubes of edge
// h, each split into six Kuhn tets (BlockMesher's split), keeping the cubes whose centre lies
// inside the surface, so the mesh's volume (and mass) matches the surface's to within the
// staircase error. The visual surface is then embedded in the result (SurfaceEmbedding), the
// vertices just outside tied to the nearest tet, rather than matched by it.
//
// Why a lattice and not TetGen, Gmsh or CGAL: the simulation mesh only has to carry the visual
// surface, not conform to it; a lattice is robust on imperfect organ surfaces (small holes,
// slivers, self-touching parts), fast (linear in cells plus triangles), has a guaranteed
// quality (all tets congruent to Kuhn's: minimum dihedral angle 45 degrees, no slivers) and a
// predictable spring count, and needs no library: TetGen is AGPL, Gmsh GPL and CGAL's mesher
// GPL, none of which a training product can ship without taking on their terms.
//
// Inside: a cube centre is inside when a majority of three axis-aligned rays cast through it
// cross the surface an odd number of times before it (ray parity, robust to one bad direction).

#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {

struct LatticeOptions {
  double edgeLength_m = 0.0;  ///< cube edge h (> 0)
};

/// @throws MeshFileError (via std::invalid_argument wording) when h <= 0 or nothing is inside.
TetMesh meshInterior(const TriangleSurface& surface, const LatticeOptions& options);

/// The edge length whose lattice gives about `targetSprings` springs for this surface
/// (measured, by a few trial meshes).
double edgeLengthForSpringCount(const TriangleSurface& surface, int targetSprings);

}  // namespace tissuesim
