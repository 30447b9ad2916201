#include "analysis/FemTensileTest.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/QuadraticTetMesh.h"
#include "mesh/BlockMesher.h"

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
  if (specimen.cellsAcrossThickness < 1)
    throw std::invalid_argument("--resolution must be at least 1 cell across the thickness");
  const Eigen::Vector3d& size = specimen.size_m;
  const double h = size.z() / specimen.cellsAcrossThickness;
  const Eigen::Vector3i cells(std::max(1, static_cast<int>(std::lround(size.x() / h))),
                              std::max(1, static_cast<int>(std::lround(size.y() / h))),
                              specimen.cellsAcrossThickness);
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(makeBlockMesh(size, cells));
  const FemModel model(mesh, energy, bulkModulus_Pa);

  // The grips of TensileTest.h: x = 0 held in x, x = L moved in x, three DOFs against rigid
  // motion.
  std::vector<char> isFixed(static_cast<std::size_t>(3 * mesh.nodeCount()), 0);
  std::vector<Eigen::Index> moving;
  const auto fix = [&](Eigen::Index node, int axis) {
    isFixed[static_cast<std::size_t>(3 * node + axis)] = 1;
  };
  constexpr double kOnFace = 1e-12;
  for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
    const Eigen::Vector3d p = mesh.nodes_m.col(i);
    if (std::abs(p.x()) < kOnFace) {
      fix(i, 0);
      if (p.y() < kOnFace && p.z() < kOnFace) {
        fix(i, 1);
        fix(i, 2);
      }
      if (std::abs(p.y() - size.y()) < kOnFace && p.z() < kOnFace) fix(i, 2);
      if (p.y() < kOnFace && std::abs(p.z() - size.z()) < kOnFace) fix(i, 1);
    }
    if (std::abs(p.x() - size.x()) < kOnFace) {
      fix(i, 0);
      moving.push_back(i);
    }
  }

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
      for (const Eigen::Index node : moving) x(0, node) = lambda * size.x();
      currentStretch = lambda;
      // Tolerance relative to the grip force, as TensileTest's: round-off in the forces grows
      // with them (and with the stiff volumetric term).
      // The floor: the stiff volumetric term's round-off leaves about 1e-9 N at rest.
      solver.setTolerance(kForceTolerance * std::max(10.0, std::abs(lastReaction_N)));
      const FemSolveReport report = solver.solve(model, x, isFixed);
      double reaction_N = 0.0;
      for (const Eigen::Index node : moving) reaction_N += solver.gradient()(0, node);
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
