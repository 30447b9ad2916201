// SPDX-License-Identifier: Apache-2.0
// The FEM reference: its forces are its energy's gradient and its Hessian the gradient's
// derivative (finite differences), a homogeneous stretch of one cube matches the closed form of
// the same energy, and the meshed tensile specimen reproduces the continuum's uniaxial curve.

#include "fem/FemModel.h"

#include <random>

#include <gtest/gtest.h>

#include "analysis/FemTensileExperiment.h"
#include "analysis/GoodnessOfFit.h"
#include "analysis/UniaxialModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/IsochoricMaterialPoint.h"
#include "mesh/BlockMesher.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

/// A 2 x 1 x 1 cell block of quadratic tets, stretched 15 % along x and jiggled.
struct DeformedQuadraticBlock {
  QuadraticTetMesh mesh = makeQuadraticTetMesh(makeBlockMesh({0.02, 0.01, 0.01}, {2, 1, 1}));
  FemModel model{mesh, test::liverEnergy(), 50.0 * test::liverEnergy().initialShearModulus()};
  test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 3, 2e-4);
  const Eigen::Matrix3Xd& x = deformed.x;
  const Eigen::Matrix3Xd& direction = deformed.direction;
};

TEST(FemModel, TheGradientIsTheEnergysDerivative) {
  const DeformedQuadraticBlock block;
  Eigen::Matrix3Xd gradient;
  ASSERT_TRUE(block.model.evaluate(block.x, gradient).isAdmissible);
  constexpr double h = 1e-7;
  const double slope = (block.model.evaluate(block.x + h * block.direction).energy_J -
                        block.model.evaluate(block.x - h * block.direction).energy_J) /
                       (2.0 * h);
  const double expected = gradient.cwiseProduct(block.direction).sum();
  ASSERT_GT(std::abs(expected), 1e-6);
  EXPECT_NEAR(slope, expected, 1e-6 * std::abs(expected));
}

TEST(FemModel, TheHessianIsTheGradientsDerivative) {
  const DeformedQuadraticBlock block;
  Eigen::Matrix3Xd gradient, plus, minus;
  Eigen::SparseMatrix<double> hessian;
  block.model.evaluate(block.x, gradient, hessian, {});
  constexpr double h = 1e-8;
  block.model.evaluate(block.x + h * block.direction, plus);
  block.model.evaluate(block.x - h * block.direction, minus);
  const Eigen::Matrix3Xd difference = (plus - minus) / (2.0 * h);
  const Eigen::VectorXd expected =
      Eigen::Map<const Eigen::VectorXd>(difference.data(), difference.size());
  const Eigen::VectorXd product =
      hessian * Eigen::Map<const Eigen::VectorXd>(block.direction.data(), block.direction.size());
  EXPECT_LT((product - expected).cwiseAbs().maxCoeff(), 1e-5 * expected.cwiseAbs().maxCoeff());
  EXPECT_LT((Eigen::MatrixXd(hessian) - Eigen::MatrixXd(hessian).transpose()).cwiseAbs().maxCoeff(),
            1e-9 * expected.cwiseAbs().maxCoeff() / block.direction.cwiseAbs().maxCoeff());
}

/// The closed form of the same energy in homogeneous uniaxial stretch: F = diag(lambda, s, s),
/// s such that the lateral stress vanishes; returns P_11 (Pa).
double closedFormUniaxialStress(double lambda, double bulkModulus_Pa) {
  const auto stress = [&](double s) {
    Eigen::Matrix3d f = Eigen::Vector3d(lambda, s, s).asDiagonal();
    const double j = f.determinant();
    // P = P_iso + U'(J) cof F, cof F = J F^-T.
    return Eigen::Matrix3d(evaluateIsochoric(test::liverEnergy(), f, false).stress_Pa +
                           bulkModulus_Pa * (j - 1.0) * j * f.inverse().transpose());
  };
  double low = 0.5, high = 1.0;  // P_22 < 0 at s = 0.5 (squeezed), > 0 at s = 1
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (low + high);
    (stress(mid)(1, 1) > 0.0 ? high : low) = mid;
  }
  return stress(0.5 * (low + high))(0, 0);
}

TEST(FemModel, ACubeInHomogeneousStretchMatchesTheClosedForm) {
  // One cube, six quadratic tets, the tensile grips: its equilibrium is homogeneous, which the
  // quadratic element represents exactly, so the grip stress is the closed form's.
  const double kappa = 1e3 * test::liverEnergy().initialShearModulus();
  for (const double lambda : {1.05, 1.2, 1.3}) {
    const TensileSpecimen cube{{0.01, 0.01, 0.01}, 1};
    FemTensileStats stats;
    const std::vector<CurveBranch> curve =
        runFemTensileTest(test::liverEnergy(), cube, kappa, {{lambda}, 2}, &stats);
    EXPECT_EQ(stats.elements, 6);
    EXPECT_EQ(stats.unconvergedPoints, 0);
    const double expected = closedFormUniaxialStress(lambda, kappa);
    EXPECT_NEAR(curve[0].stress_Pa.back(), expected, 1e-6 * expected) << lambda;
  }
}

TEST(FemModel, TheTensileSpecimenReproducesTheContinuumCurve) {
  // The default bulk modulus holds the volume: the virgin loading curve to lambda 1.3 against
  // sedf's (the incompressible continuum's), R^2 >= 0.9999, the volume within 0.1 %.
  const StrainEnergy& energy = test::liverEnergy();
  const UniaxialProtocol protocol{{1.3}, 13};
  FemTensileStats stats;
  const std::vector<CurveBranch> fem = runFemTensileTest(
      energy, {{0.055, 0.020, 0.005}, 1}, defaultFemBulkModulus(energy), protocol, &stats);
  std::vector<double> expected;
  for (const double lambda : fem[0].stretch) expected.push_back(energy.stress(lambda));
  EXPECT_EQ(stats.unconvergedPoints, 0);
  EXPECT_GE(coefficientOfDetermination(expected, fem[0].stress_Pa), 0.9999);
  EXPECT_GT(stats.minVolumeRatio, 0.999);
  EXPECT_LT(stats.maxVolumeRatio, 1.001);
  // A bulk modulus set from mu0 does not: Poisson 0.49 at rest (kappa = 50 mu0) leaves the
  // stiffened tissue compressible, tens of percent soft at lambda 1.3.
  const std::vector<CurveBranch> soft = runFemTensileTest(
      energy, {{0.055, 0.020, 0.005}, 1}, 50.0 * energy.initialShearModulus(), protocol);
  EXPECT_LT(soft[0].stress_Pa.back(), 0.9 * expected.back());
}

}  // namespace
}  // namespace tissuesim
