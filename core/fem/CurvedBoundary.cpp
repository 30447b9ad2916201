// SPDX-License-Identifier: Apache-2.0
#include "fem/CurvedBoundary.h"

#include <algorithm>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "fem/QuadraticTetShape.h"
#include "mesh/ClosestSurfacePoint.h"

namespace tissuesim {

namespace {

/// Where det(dX/dxi) is sampled: the corners, the edges' middles, the degree-3 rule's points.
std::vector<Eigen::Vector3d> jacobianSamples() {
  std::vector<Eigen::Vector3d> samples = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
                                          Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  for (int e = 0; e < 6; ++e) {
    const int i = kQuadraticTetEdges[e][0];
    const int j = kQuadraticTetEdges[e][1];
    samples.push_back(
        0.5 * (samples[static_cast<std::size_t>(i)] + samples[static_cast<std::size_t>(j)]));
  }
  for (const TetQuadraturePoint& point : tetQuadratureDegree3()) samples.push_back(point.xi);
  return samples;
}

}  // namespace

double leastJacobianShare(const QuadraticTetMesh& quadratic, Eigen::Index t) {
  static const std::vector<Eigen::Vector3d> samples = jacobianSamples();
  const Eigen::Vector3d x0 = quadratic.nodes_m.col(quadratic.tets(0, t));
  Eigen::Matrix3d edges;
  for (int c = 0; c < 3; ++c) edges.col(c) = quadratic.nodes_m.col(quadratic.tets(c + 1, t)) - x0;
  const double straight = edges.determinant();
  double least = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& xi : samples)
    least = std::min(least, quadraticTetJacobian(quadratic, t, xi).determinant());
  return least / straight;
}

CurvedBoundaryReport curveBoundaryOnto(QuadraticTetMesh& quadratic, const TetMesh& linear,
                                       const TriangleSurface& surface) {
  if (quadratic.cornerCount != linear.nodeCount() || quadratic.tetCount() != linear.tetCount())
    throw std::invalid_argument("curveBoundaryOnto: the quadratic mesh is not the linear one's");
  // Each edge's middle node, and the tets round it.
  const QuadraticEdgeMiddles middleOf = edgeMiddles(quadratic);
  std::vector<std::vector<int>> tetsRound(static_cast<std::size_t>(quadratic.nodeCount()));
  for (Eigen::Index t = 0; t < quadratic.tetCount(); ++t) {
    for (int e = 0; e < 6; ++e)
      tetsRound[static_cast<std::size_t>(quadratic.tets(4 + e, t))].push_back(static_cast<int>(t));
  }
  // Each boundary edge's middle node and the outward normal of its faces (their areas' sum).
  struct BoundaryEdge {
    int middle;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  };
  std::map<std::pair<int, int>, BoundaryEdge> boundaryEdges;  // ordered: no hash in the result
  const Eigen::Matrix3Xi faces = boundaryFaces(linear);
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const Eigen::Vector3d areaNormal =
        (linear.nodes_m.col(faces(1, f)) - linear.nodes_m.col(faces(0, f)))
            .cross(linear.nodes_m.col(faces(2, f)) - linear.nodes_m.col(faces(0, f)));
    for (int k = 0; k < 3; ++k) {
      const int a = faces(k, f);
      const int b = faces((k + 1) % 3, f);
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      boundaryEdges.try_emplace(key, BoundaryEdge{middleOf.at(key)}).first->second.normal +=
          areaNormal;
    }
  }
  CurvedBoundaryReport report;
  report.boundaryEdges = static_cast<int>(boundaryEdges.size());
  if (surface.triangleCount() == 0) {
    report.left = report.boundaryEdges;
    return report;
  }
  const ClosestSurfacePoint closest(surface);
  std::vector<double> cornerOffset_m(static_cast<std::size_t>(quadratic.cornerCount), -1.0);
  const auto offsetOf = [&](int corner) {
    double& offset = cornerOffset_m[static_cast<std::size_t>(corner)];
    if (offset < 0.0) {
      const Eigen::Vector3d at = quadratic.nodes_m.col(corner);
      offset = (closest(at) - at).norm();
    }
    return offset;
  };
  for (const auto& [edge, boundary] : boundaryEdges) {
    const int middle = boundary.middle;
    const double length_m =
        (quadratic.nodes_m.col(edge.first) - quadratic.nodes_m.col(edge.second)).norm();
    if (offsetOf(edge.first) > kCornerOnSurface * length_m ||
        offsetOf(edge.second) > kCornerOnSurface * length_m) {
      ++report.left;
      continue;
    }
    const Eigen::Vector3d chordMiddle = quadratic.nodes_m.col(middle);
    const Eigen::Vector3d target = closest(chordMiddle);
    const double move_m = (target - chordMiddle).norm();
    if (move_m > kLongestMove * length_m) {
      ++report.left;
      continue;
    }
    // Out along the faces' normal from a chord inside the surface (where it bulges), in from one
    // outside it (where it is hollow): a closest point the other way is another sheet of the
    // surface, across a part thinner than the chord's sag (a thin rim), not this one.
    if (move_m > 1e-9 * length_m) {
      const double inside = windingNumber(surface, chordMiddle) > 0.5 ? 1.0 : -1.0;
      if (inside * (target - chordMiddle).dot(boundary.normal.normalized()) <
          kLeastNormalShare * move_m) {
        ++report.left;
        continue;
      }
    }
    const std::vector<int>& round = tetsRound[static_cast<std::size_t>(middle)];
    bool isPlaced = false;
    for (double share = 1.0; share >= 0.25 && !isPlaced; share *= 0.5) {
      quadratic.nodes_m.col(middle) = chordMiddle + share * (target - chordMiddle);
      isPlaced = std::all_of(round.begin(), round.end(), [&](int t) {
        return leastJacobianShare(quadratic, t) >= kLeastJacobianShare;
      });
      if (isPlaced) {
        ++(share < 1.0 ? report.shortened : report.bent);
        report.largestMove_m = std::max(report.largestMove_m, share * move_m);
      }
    }
    if (!isPlaced) {
      quadratic.nodes_m.col(middle) = chordMiddle;
      ++report.left;
    }
  }
  return report;
}

}  // namespace tissuesim
