// SPDX-License-Identifier: Apache-2.0
#pragma once
// A quadratic (10-node) tetrahedral mesh made from a linear one: each tet keeps its four corners
// and gains a node at the middle of each edge (shared between the tets around the edge), its edges
// straight as made: the map from the reference tet is affine then, and quadratic once a middle
// node is moved off its edge's middle (the boundary bent onto a drawn surface:
// fem/CurvedBoundary.h; the FEM takes dX/dxi at each quadrature point, fem/QuadraticTetShape.h).
//
// Node order in a tet (VTK's quadratic tetra): corners 0-3, then the midpoints of the edges
// (0,1), (1,2), (0,2), (0,3), (1,3), (2,3). Shapes: nodes 3 by #V (m), tets 10 by #T; the first
// #corners nodes are the linear mesh's, in its order.

#include <map>
#include <utility>

#include <Eigen/Core>

#include "mesh/TetMesh.h"

namespace tissuesim {

using QuadraticTets = Eigen::Matrix<int, 10, Eigen::Dynamic>;

struct QuadraticTetMesh {
  Eigen::Matrix3Xd nodes_m;
  QuadraticTets tets;
  Eigen::Index cornerCount = 0;

  Eigen::Index nodeCount() const { return nodes_m.cols(); }
  Eigen::Index tetCount() const { return tets.cols(); }
};

/// The corners of edge e (0-5) of a tet, as positions in the tet's node list.
inline constexpr int kQuadraticTetEdges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};

/// @throws std::invalid_argument when `mesh` has a tet that is not positively oriented.
QuadraticTetMesh makeQuadraticTetMesh(const TetMesh& mesh);

/// Each edge's middle node, keyed by its corners (smaller index first).
using QuadraticEdgeMiddles = std::map<std::pair<int, int>, int>;
QuadraticEdgeMiddles edgeMiddles(const QuadraticTetMesh& mesh);

}  // namespace tissuesim
