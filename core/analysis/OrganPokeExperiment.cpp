// SPDX-License-Identifier: Apache-2.0
#include "analysis/OrganPokeExperiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/QuadraticTetMesh.h"
#include "forces/CapsulePenalty.h"

namespace tissuesim {
namespace {

/// The probe's shaft beyond the tip's hemisphere (m): longer than any organ is deep.
constexpr double kShaftLength_m = 0.3;

/// Each quadratic boundary node's share of the surface (m^2): the linear boundary's faces, each
/// cut into four at its edges' midpoints, a third of each piece to each of its corners.
std::map<int, double> surfaceShares(const TetMesh& organ, const QuadraticTetMesh& quadratic) {
  std::map<std::pair<int, int>, int> midpointOf;
  for (Eigen::Index t = 0; t < quadratic.tetCount(); ++t) {
    for (int e = 0; e < 6; ++e) {
      const int a = quadratic.tets(kQuadraticTetEdges[e][0], t);
      const int b = quadratic.tets(kQuadraticTetEdges[e][1], t);
      midpointOf[{std::min(a, b), std::max(a, b)}] = quadratic.tets(4 + e, t);
    }
  }
  const auto midpoint = [&](int a, int b) {
    return midpointOf.at({std::min(a, b), std::max(a, b)});
  };
  std::map<int, double> shares;
  const Eigen::Matrix3Xi faces = boundaryFaces(organ);
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const int a = faces(0, f), b = faces(1, f), c = faces(2, f);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    for (const std::array<int, 3>& piece :
         {std::array<int, 3>{a, ab, ca}, std::array<int, 3>{ab, b, bc},
          std::array<int, 3>{ca, bc, c}, std::array<int, 3>{ab, bc, ca}}) {
      const Eigen::Vector3d p0 = quadratic.nodes_m.col(piece[0]);
      const double area =
          0.5 *
          (quadratic.nodes_m.col(piece[1]) - p0).cross(quadratic.nodes_m.col(piece[2]) - p0).norm();
      for (const int node : piece) shares[node] += area / 3.0;
    }
  }
  return shares;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

bool firstCrossing(const Eigen::Matrix3Xd& vertices, const Eigen::Matrix3Xi& faces,
                   const Eigen::Vector3d& from, const Eigen::Vector3d& direction,
                   Eigen::Vector3d& crossing_m) {
  // Moeller-Trumbore, the nearest crossing ahead of `from`.
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const Eigen::Vector3d a = vertices.col(faces(0, f));
    const Eigen::Vector3d ab = vertices.col(faces(1, f)) - a;
    const Eigen::Vector3d ac = vertices.col(faces(2, f)) - a;
    const Eigen::Vector3d p = direction.cross(ac);
    const double determinant = ab.dot(p);
    if (std::abs(determinant) < 1e-30) continue;  // the ray runs along the face's plane
    const Eigen::Vector3d s = from - a;
    const double u = s.dot(p) / determinant;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(ab);
    const double v = direction.dot(q) / determinant;
    if (v < 0.0 || u + v > 1.0) continue;
    const double distance = ac.dot(q) / determinant;
    if (distance >= 0.0 && distance < nearest) nearest = distance;
  }
  if (!std::isfinite(nearest)) return false;
  crossing_m = from + nearest * direction;
  return true;
}

IndentationCurve pokeOrganFem(const StrainEnergy& energy, const TetMesh& organ,
                              const OrganPokeSetup& setup, double bulkModulus_Pa,
                              const std::function<void(double, double)>& onDepth) {
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t d = 0; d < setup.depths_m.size(); ++d) {
    if (!(setup.depths_m[d] > (d > 0 ? setup.depths_m[d - 1] : 0.0)))
      throw std::invalid_argument("poke depths must increase, each above 0");
  }
  const Eigen::Vector3d direction = setup.direction.normalized();
  Eigen::Vector3d entry;
  if (!firstCrossing(organ.nodes_m, boundaryFaces(organ), setup.tipStart_m, direction, entry))
    throw std::invalid_argument("the probe's axis does not meet the organ's surface");

  const QuadraticTetMesh mesh = makeQuadraticTetMesh(organ);
  FemModel model(mesh, energy, bulkModulus_Pa);
  std::vector<char> isFixed(static_cast<std::size_t>(3 * mesh.nodeCount()), 0);
  int fixedCount = 0;
  for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
    if (setup.fixedBox_m.contains(mesh.nodes_m.col(i))) {
      std::fill_n(isFixed.begin() + 3 * i, 3, char{1});
      ++fixedCount;
    }
  }
  if (fixedCount == 0) throw std::invalid_argument("no node of the organ lies in the fixed box");

  std::vector<CapsulePenalty::Point> points;
  for (const auto& [node, share] : surfaceShares(organ, mesh)) {
    if ((mesh.nodes_m.col(node) - entry).norm() > setup.contactReach_m) continue;
    points.push_back({{node, node, node}, {1.0, 0.0, 0.0}, share * setup.pressureStiffness_Pa_m});
  }
  CapsulePenalty probe(std::move(points));
  probe.radius_m = setup.probeRadius_m;
  model.setExtraEnergy(&probe);

  IndentationCurve curve;
  curve.nodes = static_cast<int>(mesh.nodeCount());
  curve.elements = static_cast<int>(mesh.tetCount());
  FemStaticSolver solver;
  Eigen::Matrix3Xd x = mesh.nodes_m;
  const auto force = [&] { return probe.reaction(x).dot(-direction); };
  double depth = 0.0;
  double lastForce_N = 0.0;
  for (const double target : setup.depths_m) {
    const int steps = static_cast<int>(std::ceil((target - depth) / setup.depthStep_m - 1e-9));
    const double from = depth;
    for (int s = 1; s <= steps; ++s) {
      depth = from + (target - from) * s / steps;
      // The hemisphere's centre a radius behind the tip, the tip `depth` past the entry.
      probe.tip_m = entry + (depth - setup.probeRadius_m) * direction;
      probe.top_m = probe.tip_m - kShaftLength_m * direction;
      // Relative to the force at the last equilibrium (round-off grows with it), not at the
      // start of this solve, where the probe has just moved into the surface.
      solver.setTolerance(1e-9 * std::max(1.0, std::abs(lastForce_N)));
      const FemSolveReport report = solver.solve(model, x, isFixed);
      curve.worstResidual_N = std::max(curve.worstResidual_N, report.residual_N);
      if (!report.converged) ++curve.unconvergedPoints;
      lastForce_N = force();
    }
    curve.force_N.push_back(lastForce_N);
    if (onDepth) onDepth(target, lastForce_N);
  }
  curve.seconds = secondsSince(start);
  return curve;
}

}  // namespace tissuesim
