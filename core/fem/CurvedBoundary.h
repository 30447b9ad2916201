// SPDX-License-Identifier: Apache-2.0
#pragma once
// A quadratic tet mesh's boundary bent onto the drawn surface it was meshed from: the middle
// node of each boundary edge moved from the chord's middle to the surface's closest point, so
// that each boundary face is a curved (isoparametric) quadratic patch through the surface
// (Ciarlet and Raviart, Comput. Methods Appl. Mech. Eng. 1972, 1:217-249). A straight chord of
// length h across a surface of curvature radius R lies up to h^2 / (8 R) inside it: 0.1 mm for a
// 4 mm edge on a 20 mm radius, a tenth of the first millimetre a probe presses. The curved face
// lies within O(h^3 / R^2) of the surface, and the probe meets the tissue where it is drawn.
//
// An edge is bent only where both its corners lie on the surface (within kCornerOnSurface of the
// edge's length: a mesh conformal to the surface, as Gmsh's and the refinement's are), by a move
// of at most kLongestMove of its length, and along the normal of its boundary faces (the move's
// share along it at least kLeastNormalShare: outward where the chord lies inside the surface,
// inward where outside; a closest point the other way is on another sheet of the surface, across
// a part thinner than the chord's sag). The move is halved, up to twice, where it would
// leave one of the tets round the edge with det(dX/dxi) below kLeastJacobianShare of its
// straight value at any of its corners, edge middles and volume quadrature points (the sampled
// determinant of the quadratic map: QuadraticTetShape.h), and refused where even a quarter would.
// Shapes: nodes 3 by #V (m); the linear mesh is the one the quadratic mesh was made from.

#include "fem/QuadraticTetMesh.h"
#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {

struct CurvedBoundaryReport {
  int boundaryEdges = 0;  ///< edges of the linear mesh's boundary faces
  int bent = 0;           ///< whose middle node was put on the surface
  int shortened = 0;      ///< moved only part of the way (half or a quarter)
  int left = 0;           ///< left straight: a corner off the surface, a move too long, across
                          ///< the body to another sheet, or folding a tet even at a quarter
  double largestMove_m = 0.0;
};

inline constexpr double kCornerOnSurface = 0.01;
inline constexpr double kLongestMove = 0.25;
inline constexpr double kLeastNormalShare = 0.5;
inline constexpr double kLeastJacobianShare = 0.2;

/// Bends `quadratic`'s boundary edges onto `surface` (above). `linear`: the mesh `quadratic`
/// was made from (makeQuadraticTetMesh). @throws std::invalid_argument where they differ.
CurvedBoundaryReport curveBoundaryOnto(QuadraticTetMesh& quadratic, const TetMesh& linear,
                                       const TriangleSurface& surface);

/// The smallest det(dX/dxi) of tet t over the corners, edge middles and the degree-3 rule's
/// points, over its straight value (6 V of the corners' tet): 1 on a straight-edged tet.
double leastJacobianShare(const QuadraticTetMesh& quadratic, Eigen::Index t);

}  // namespace tissuesim
