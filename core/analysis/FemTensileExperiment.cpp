// SPDX-License-Identifier: Apache-2.0
#include "analysis/FemTensileExperiment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/QuadraticTetMesh.h"

namespace tissuesim {

std::vector<CurveBranch> runFemTensileTest(const StrainEnergy& energy,
                                           const TensileSpecimen& specimen, double bulkModulus_Pa,
                                           const UniaxialProtocol& protocol,
                                           FemTensileStats* stats) {
  if (protocol.lambdaMax.empty() || protocol.pointsPerBranch < 2)
    throw std::invalid_argument("a tensile protocol needs a lambda_max and 2 points a branch");
  for (const double peak : protocol.lambdaMax) {
    if (!(peak > 1.0) || peak > energy.usableRange().upper) {
      throw std::invalid_argument("lambda_max " + std::to_string(peak) + " is outside (1, " +
                                  std::to_string(energy.usableRange().upper) +
                                  "], where this tissue is usable");
    }
  }
  const Eigen::Vector3d& size = specimen.size_m;
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(makeTensileSpecimenMesh(specimen));
  const FemModel model(mesh, energy, bulkModulus_Pa);
  // TensileExperiment's grips, on the quadratic mesh's nodes (its edge midpoints among them).
  std::vector<int> moving;
  const std::vector<char> isFixed = tensileGripDofs(mesh.nodes_m, size, moving);

  FemTensileStats local;
  local.nodes = static_cast<int>(mesh.nodeCount());
  local.elements = static_cast<int>(mesh.tetCount());
  constexpr double kForceTolerance = 1e-9;  // N per N of grip force
  FemStaticSolver solver(kForceTolerance);
  double lastReaction_N = 0.0;
  Eigen::Matrix3Xd x = mesh.nodes_m;
  double currentStretch = 1.0;
  const double section = size.y() * size.z();
  std::vector<CurveBranch> branches = protocolStretches(protocol);
  for (CurveBranch& branch : branches) {
    for (const double lambda : branch.stretch) {
      // Affine predictor from the last equilibrium: along x by the ratio, across by its
      // incompressible counterpart.
      const double ratio = lambda / currentStretch;
      x.row(0) *= ratio;
      x.bottomRows(2) *= 1.0 / std::sqrt(ratio);
      for (const int node : moving) x(0, node) = lambda * size.x();
      currentStretch = lambda;
      // Tolerance relative to the grip force, as TensileExperiment's: round-off in the forces grows
      // with them (and with the stiff volumetric term).
      // The floor: the stiff volumetric term's round-off leaves about 1e-9 N at rest.
      solver.setTolerance(kForceTolerance * std::max(10.0, std::abs(lastReaction_N)));
      const FemSolveReport report = solver.solve(model, x, isFixed);
      double reaction_N = 0.0;
      for (const int node : moving) reaction_N += solver.gradient()(0, node);
      if (!report.converged) ++local.unconvergedPoints;
      local.worstIterations = std::max(local.worstIterations, report.iterations);
      local.worstResidual_N = std::max(local.worstResidual_N, report.residual_N);
      local.minVolumeRatio = std::min(local.minVolumeRatio, report.state.minVolumeRatio);
      local.maxVolumeRatio = std::max(local.maxVolumeRatio, report.state.maxVolumeRatio);
      lastReaction_N = reaction_N;
      branch.stress_Pa.push_back(reaction_N / section);
    }
  }
  if (stats != nullptr) *stats = local;
  return branches;
}

}  // namespace tissuesim
