// SPDX-License-Identifier: Apache-2.0
#include "analysis/OrganPokeExperiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include "analysis/SecondsSince.h"
#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/QuadraticTetMesh.h"
#include "forces/CapsulePenalty.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {
namespace {

/// The probe's shaft beyond the tip's hemisphere (m): longer than any organ is deep.
constexpr double kShaftLength_m = 0.3;

/// Each quadratic boundary node's share of the surface (m^2; 0 off the surface): the linear
/// boundary's faces, each cut into four at its edges' midpoints.
Eigen::VectorXd surfaceShares(const TetMesh& organ, const QuadraticTetMesh& quadratic) {
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
  const Eigen::Matrix3Xi faces = boundaryFaces(organ);
  Eigen::Matrix3Xi pieces(3, 4 * faces.cols());
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const int a = faces(0, f), b = faces(1, f), c = faces(2, f);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    pieces.middleCols<4>(4 * f) << a, ab, ca, ab,  //
        ab, b, bc, bc,                             //
        ca, bc, c, ca;
  }
  return vertexAreas(quadratic.nodes_m, pieces);
}

}  // namespace

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
  const Eigen::VectorXd shares = surfaceShares(organ, mesh);
  for (int node = 0; node < static_cast<int>(shares.size()); ++node) {
    if (!(shares[node] > 0.0) || (mesh.nodes_m.col(node) - entry).norm() > setup.contactReach_m)
      continue;
    points.push_back(
        {{node, node, node}, {1.0, 0.0, 0.0}, shares[node] * setup.pressureStiffness_Pa_m});
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
      const auto solveStart = std::chrono::steady_clock::now();
      const FemSolveReport report = solver.solve(model, x, isFixed);
      curve.solving_s += secondsSince(solveStart);
      curve.newtonIterations += report.iterations;
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
