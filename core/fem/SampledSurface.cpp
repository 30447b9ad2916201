// SPDX-License-Identifier: Apache-2.0
#include "fem/SampledSurface.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace tissuesim {

Eigen::Matrix3Xi quadraticSurfacePieces(const TetMesh& linear, const QuadraticTetMesh& quadratic) {
  const QuadraticEdgeMiddles midpointOf = edgeMiddles(quadratic);
  const auto midpoint = [&](int a, int b) {
    return midpointOf.at({std::min(a, b), std::max(a, b)});
  };
  const Eigen::Matrix3Xi faces = boundaryFaces(linear);
  Eigen::Matrix3Xi pieces(3, 4 * faces.cols());
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const int a = faces(0, f), b = faces(1, f), c = faces(2, f);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    pieces.middleCols<4>(4 * f) << a, ab, ca, ab,  //
        ab, b, bc, bc,                             //
        ca, bc, c, ca;
  }
  return pieces;
}

std::vector<CapsulePenalty::Point> sampleSurfacePoints(
    const QuadraticTetMesh& quadratic, const Eigen::Matrix3Xi& pieces, double spacing_m,
    double pressureStiffness_Pa_m, const Eigen::Vector3d& centre_m, double reach_m) {
  std::vector<CapsulePenalty::Point> points;
  for (Eigen::Index f = 0; f < pieces.cols(); ++f) {
    const Eigen::Vector3d a = quadratic.nodes_m.col(pieces(0, f));
    const Eigen::Vector3d b = quadratic.nodes_m.col(pieces(1, f));
    const Eigen::Vector3d c = quadratic.nodes_m.col(pieces(2, f));
    if (((a + b + c) / 3.0 - centre_m).norm() > reach_m) continue;
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const int cuts = std::max(1, static_cast<int>(std::ceil(std::sqrt(2.0 * area) / spacing_m)));
    const double share = area / (cuts * cuts) * pressureStiffness_Pa_m;
    for (int i = 0; i < cuts; ++i) {
      for (int j = 0; i + j < cuts; ++j) {
        // The upright small triangle at (i, j), and the inverted one beside it.
        for (int flip = 0; flip < (i + j + 1 < cuts ? 2 : 1); ++flip) {
          const double u = (i + (flip == 0 ? 1.0 : 2.0) / 3.0) / cuts;
          const double v = (j + (flip == 0 ? 1.0 : 2.0) / 3.0) / cuts;
          points.push_back(
              {{pieces(0, f), pieces(1, f), pieces(2, f)}, {1.0 - u - v, u, v}, share});
        }
      }
    }
  }
  return points;
}

}  // namespace tissuesim
