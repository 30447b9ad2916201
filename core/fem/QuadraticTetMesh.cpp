// SPDX-License-Identifier: Apache-2.0
#include "fem/QuadraticTetMesh.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace tissuesim {

QuadraticTetMesh makeQuadraticTetMesh(const TetMesh& mesh) {
  QuadraticTetMesh quadratic;
  quadratic.cornerCount = mesh.nodeCount();
  quadratic.tets.resize(10, mesh.tetCount());
  std::map<std::pair<int, int>, int> midpointOf;
  std::vector<Eigen::Vector3d> midpoints;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    if (!(signedTetVolume(mesh.nodes_m, mesh.tets, t) > 0.0)) {
      throw std::invalid_argument("tet " + std::to_string(t) +
                                  " is not positively oriented: no quadratic element on it");
    }
    for (int i = 0; i < 4; ++i) quadratic.tets(i, t) = mesh.tets(i, t);
    for (int e = 0; e < 6; ++e) {
      const int a = mesh.tets(kQuadraticTetEdges[e][0], t);
      const int b = mesh.tets(kQuadraticTetEdges[e][1], t);
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      auto [at, isNew] = midpointOf.try_emplace(
          key,
          static_cast<int>(quadratic.cornerCount + static_cast<Eigen::Index>(midpoints.size())));
      if (isNew) midpoints.push_back(0.5 * (mesh.nodes_m.col(a) + mesh.nodes_m.col(b)));
      quadratic.tets(4 + e, t) = at->second;
    }
  }
  quadratic.nodes_m.resize(3, quadratic.cornerCount + static_cast<Eigen::Index>(midpoints.size()));
  quadratic.nodes_m.leftCols(quadratic.cornerCount) = mesh.nodes_m;
  for (std::size_t m = 0; m < midpoints.size(); ++m)
    quadratic.nodes_m.col(quadratic.cornerCount + static_cast<Eigen::Index>(m)) = midpoints[m];
  return quadratic;
}

QuadraticEdgeMiddles edgeMiddles(const QuadraticTetMesh& mesh) {
  QuadraticEdgeMiddles middles;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (int e = 0; e < 6; ++e) {
      const int a = mesh.tets(kQuadraticTetEdges[e][0], t);
      const int b = mesh.tets(kQuadraticTetEdges[e][1], t);
      middles[{std::min(a, b), std::max(a, b)}] = mesh.tets(4 + e, t);
    }
  }
  return middles;
}

}  // namespace tissuesim
