// SPDX-License-Identifier: Apache-2.0
#include "springs/SmallStrainCalibration.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include <Eigen/SparseCholesky>

#include "numerics/NodeBlockMatrix.h"
#include "springs/SpringForceField.h"
#include "springs/StiffnessCouplings.h"
#include "springs/VolumeForceField.h"

namespace tissuesim {
namespace {

/// K at rest of one force field, assembled on `couplings`.
Eigen::SparseMatrix<double> restStiffness(const ForceField& field, const SpringMesh& mesh,
                                          const Eigen::Matrix2Xi& couplings) {
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, mesh.nodeCount());
  NodeBlockMatrix matrix(mesh.nodeCount(), couplings);
  matrix.setZero();
  addStiffnessAt(field, mesh.restPositions_m, false, matrix, forces);
  return matrix.matrix();
}

/// The specimen's linearised response, factorised once per stiffness.
class LinearisedSpecimen {
 public:
  LinearisedSpecimen(Eigen::SparseMatrix<double> springs, Eigen::SparseMatrix<double> volume,
                     const UniaxialGrips& grips)
      : m_springs(std::move(springs)), m_volume(std::move(volume)), m_grips(grips) {
    const Eigen::Index dofs = m_springs.rows();
    if (static_cast<Eigen::Index>(grips.isFixed.size()) != dofs || grips.movingNodes.empty() ||
        !(grips.length_m > 0.0) || !(grips.section_m2 > 0.0)) {
      throw std::invalid_argument(
          "small-strain calibration: the grips need one flag per DOF, moving nodes, a length "
          "and a section");
    }
    // The prescribed displacement: unit strain at the moving nodes.
    m_prescribed = Eigen::VectorXd::Zero(dofs);
    for (const int node : grips.movingNodes) m_prescribed[3 * node] = grips.length_m;
    std::vector<Eigen::Triplet<double>> select;
    for (Eigen::Index d = 0; d < dofs; ++d) {
      if (grips.isFixed[static_cast<std::size_t>(d)] == 0)
        select.emplace_back(d, static_cast<Eigen::Index>(select.size()), 1.0);
    }
    m_free.resize(dofs, static_cast<Eigen::Index>(select.size()));
    m_free.setFromTriplets(select.begin(), select.end());
  }

  /// E (Pa) with the springs' V_e scaled by `scale`.
  double modulus(double scale) {
    const Eigen::SparseMatrix<double> stiffness = scale * m_springs + m_volume;
    const Eigen::SparseMatrix<double> freeStiffness = m_free.transpose() * stiffness * m_free;
    if (!m_isAnalysed) {
      m_cholesky.analyzePattern(freeStiffness);
      m_isAnalysed = true;
    }
    m_cholesky.factorize(freeStiffness);
    const bool isPositive =
        m_cholesky.info() == Eigen::Success && (m_cholesky.vectorD().array() > 0.0).all();
    if (!isPositive) {
      throw std::invalid_argument(
          "small-strain calibration: the specimen's stiffness at rest is singular (the grips "
          "leave it free to move, or the law has no stiffness at rest)");
    }
    const Eigen::VectorXd freeDisplacement =
        m_cholesky.solve(-(m_free.transpose() * (stiffness * m_prescribed)));
    const Eigen::VectorXd force = stiffness * (m_prescribed + m_free * freeDisplacement);
    double reaction_N = 0.0;
    for (const int node : m_grips.movingNodes) reaction_N += force[3 * node];
    return reaction_N / m_grips.section_m2;  // strain 1
  }

 private:
  Eigen::SparseMatrix<double> m_springs;
  Eigen::SparseMatrix<double> m_volume;
  const UniaxialGrips& m_grips;
  Eigen::VectorXd m_prescribed;
  Eigen::SparseMatrix<double> m_free;  ///< 3#V by #free: selects the free DOFs
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> m_cholesky;
  bool m_isAnalysed = false;
};

LinearisedSpecimen linearise(const SpringMesh& mesh, const SpringForceLaw& law,
                             double bulkModulus_Pa, const UniaxialGrips& grips) {
  std::unique_ptr<VolumeForceField> volume;
  if (bulkModulus_Pa > 0.0) volume = std::make_unique<VolumeForceField>(mesh, bulkModulus_Pa);
  const Eigen::Matrix2Xi couplings = stiffnessCouplings(mesh, volume ? &volume->cells() : nullptr);
  const SpringForceField springs(mesh, law);
  Eigen::SparseMatrix<double> springStiffness = restStiffness(springs, mesh, couplings);
  Eigen::SparseMatrix<double> volumeStiffness =
      volume ? restStiffness(*volume, mesh, couplings)
             : Eigen::SparseMatrix<double>(springStiffness.rows(), springStiffness.cols());
  return LinearisedSpecimen(std::move(springStiffness), std::move(volumeStiffness), grips);
}

}  // namespace

double smallStrainModulus(const SpringMesh& mesh, const SpringForceLaw& law, double bulkModulus_Pa,
                          const UniaxialGrips& grips) {
  return linearise(mesh, law, bulkModulus_Pa, grips).modulus(1.0);
}

double smallStrainStiffnessScale(const SpringMesh& mesh, const SpringForceLaw& law,
                                 double bulkModulus_Pa, const UniaxialGrips& grips,
                                 double targetModulus_Pa) {
  if (!(targetModulus_Pa > 0.0)) {
    throw std::invalid_argument("small-strain calibration: the target modulus must be positive");
  }
  LinearisedSpecimen specimen = linearise(mesh, law, bulkModulus_Pa, grips);
  const double springsAlone = targetModulus_Pa / specimen.modulus(1.0);
  if (!(bulkModulus_Pa > 0.0)) return springsAlone;
  // E(c) rises smoothly and monotonically with c: secant steps from the springs' own factor.
  double previous = springsAlone;
  double previousError = specimen.modulus(previous) - targetModulus_Pa;
  double scale = previous * targetModulus_Pa / (previousError + targetModulus_Pa);
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double error = specimen.modulus(scale) - targetModulus_Pa;
    if (std::abs(error) <= 1e-10 * targetModulus_Pa) return scale;
    if (error == previousError) break;
    const double next = scale - error * (scale - previous) / (error - previousError);
    previous = scale;
    previousError = error;
    scale = next > 0.0 ? next : 0.5 * scale;
  }
  throw std::invalid_argument(
      "small-strain calibration: no factor on the springs gives the target modulus with this "
      "volume term (it is stiffer than the target on its own)");
}

}  // namespace tissuesim
