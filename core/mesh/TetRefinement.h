// SPDX-License-Identifier: Apache-2.0
#pragma once
// A tet mesh refined towards a point: edges longer than a size that grows with the distance from
// the point are bisected, each bisection splitting every tet round the edge in two at its
// midpoint, so the mesh stays conforming. A tet is only ever split at its longest edge (Rivara's
// longest-edge propagation: to split an edge that is not the longest of one of its tets, that
// tet's longest edge is split first; Rivara and Levin, Commun. Appl. Numer. Methods 1992,
// 8:281-290, for tets). In the plane this bounds how far the shapes degrade however deep the
// refinement goes (Rivara 1984); for tets the bound is observed rather than proven, and the tests
// check it on the meshes refined here.
//
// A midpoint on the boundary is moved onto the drawn surface (its closest point), when given and
// when the move neither inverts one of the new tets nor is more than a quarter of the edge long:
// the refined boundary follows the surface the coarse one cuts across in chords.
//
//   size h(x) = min(coarsest, finest + growth |x - centre|)   (m; growth per metre, unitless)
//   an edge is split when its length exceeds h at its midpoint.
//
// Shapes: nodes 3 by #V (m), tets 4 by #T. The refined mesh keeps the input's nodes first, in
// their order; each node after them is the midpoint of the edge in `splitEdges` (2 by #new,
// node indices of the refined mesh, both smaller than the new node's).

#include <Eigen/Core>

#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {

struct TetMeshGrading {
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();
  double finest_m = 0.002;
  double growth = 0.6;  ///< the size's growth per unit distance from the centre
  double coarsest_m = 0.024;

  double sizeAt(const Eigen::Vector3d& point_m) const;
};

struct RefinedTetMesh {
  TetMesh mesh;
  Eigen::Matrix2Xi splitEdges;  ///< each new node's parents
};

/// The most tets a refinement may make: past it, a grading finer than any simulation here runs
/// is refused rather than filling the memory (several times the trade map's largest network).
inline constexpr long kMaxRefinedTets = 300'000;

/// `mesh` refined to `grading`, its boundary's midpoints moved onto `surface` when it is given.
/// @throws std::invalid_argument on a grading out of range (finest_m <= 0, growth < 0,
/// coarsest_m < finest_m), a mesh with an inverted tet, or a refinement past kMaxRefinedTets.
RefinedTetMesh refineTetMesh(const TetMesh& mesh, const TetMeshGrading& grading,
                             const TriangleSurface* surface = nullptr);

}  // namespace tissuesim
