// SPDX-License-Identifier: Apache-2.0
// The FEM reference: its forces are its energy's gradient and its Hessian the gradient's
// derivative (finite differences), a homogeneous stretch of one cube matches the closed form of
// the same energy, and the meshed tensile specimen reproduces the continuum's uniaxial curve.

#include "fem/FemModel.h"

#include <algorithm>
#include <random>

#include <Eigen/Eigenvalues>

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

  /// dE/dx . direction by central differences of the energy (step 1e-7), and as the gradient gives
  /// it.
  std::pair<double, double> slopes() const {
    Eigen::Matrix3Xd gradient;
    EXPECT_TRUE(model.evaluate(x, gradient).isAdmissible);
    constexpr double h = 1e-7;
    return {
        (model.evaluate(x + h * direction).energy_J - model.evaluate(x - h * direction).energy_J) /
            (2.0 * h),
        gradient.cwiseProduct(direction).sum()};
  }
  /// The Hessian times direction against the gradient's central differences (step 1e-8): the
  /// largest entry of their difference, and of the differences; the Hessian's asymmetry.
  struct HessianCheck {
    double error, scale, asymmetry;
  };
  HessianCheck hessianAlongTheDirection() const {
    Eigen::Matrix3Xd gradient, plus, minus;
    Eigen::SparseMatrix<double> hessian;
    model.evaluate(x, gradient, hessian, {});
    constexpr double h = 1e-8;
    model.evaluate(x + h * direction, plus);
    model.evaluate(x - h * direction, minus);
    const Eigen::Matrix3Xd difference = (plus - minus) / (2.0 * h);
    const Eigen::VectorXd expected =
        Eigen::Map<const Eigen::VectorXd>(difference.data(), difference.size());
    const Eigen::VectorXd product =
        hessian * Eigen::Map<const Eigen::VectorXd>(direction.data(), direction.size());
    const Eigen::MatrixXd dense(hessian);
    return {(product - expected).cwiseAbs().maxCoeff(), expected.cwiseAbs().maxCoeff(),
            (dense - dense.transpose()).cwiseAbs().maxCoeff()};
  }
};

TEST(FemModel, TheGradientIsTheEnergysDerivative) {
  const DeformedQuadraticBlock block;
  const auto [slope, expected] = block.slopes();
  ASSERT_GT(std::abs(expected), 1e-6);
  EXPECT_NEAR(slope, expected, 1e-6 * std::abs(expected));
}

TEST(FemModel, TheHessianIsTheGradientsDerivative) {
  const DeformedQuadraticBlock block;
  const DeformedQuadraticBlock::HessianCheck check = block.hessianAlongTheDirection();
  EXPECT_LT(check.error, 1e-5 * check.scale);
  EXPECT_LT(check.asymmetry, 1e-9 * check.scale / block.direction.cwiseAbs().maxCoeff());
}

TEST(FemModel, SoftenedItsGradientAndHessianAreStillItsEnergysDerivatives) {
  // Peaks taken at 30 % isochoric stretch, the block evaluated about 15 %: every point on its
  // unloading branch (below its peak, which the block's own strains leave where it was), on its
  // softened energy, still a plain energy of x whose Hessian is its own.
  DeformedQuadraticBlock block;
  block.model.setSoftening(&test::liverSoftening());
  Eigen::Matrix3Xd peakPositions = block.mesh.nodes_m;
  peakPositions.row(0) *= 1.3;
  peakPositions.bottomRows(2) /= std::sqrt(1.3);
  block.model.softenAt(peakPositions);
  const std::vector<double> peaks = block.model.peakShifts();
  block.model.softenAt(block.x);
  ASSERT_EQ(block.model.peakShifts(), peaks);
  Eigen::Matrix3Xd gradient, virginGradient;
  block.model.evaluate(block.x, gradient);
  FemModel virgin(block.mesh, test::liverEnergy(), block.model.bulkModulus());
  virgin.evaluate(block.x, virginGradient);
  EXPECT_LT(gradient.norm(), 0.9 * virginGradient.norm());  // softened
  const auto [slope, expected] = block.slopes();
  EXPECT_NEAR(slope, expected, 1e-6 * std::abs(expected));
  const DeformedQuadraticBlock::HessianCheck check = block.hessianAlongTheDirection();
  EXPECT_LT(check.error, 1e-5 * check.scale);
}

TEST(FemModel, AStretchedBlockUnloadsOnThePapersSoftenedCurve) {
  // A homogeneous isochoric stretch diag(lambda, lambda^-1/2, lambda^-1/2): the element forces on
  // the far face sum to P_11 times its area, and P_11 unloading from lambda_max 1.3 is the virgin
  // stress times the spring law's F(lambda; 1.3) (the paper's Eq. 20; its residual term is not
  // the FEM's). Loading past the peak follows the
  // virgin curve again and raises the peak.
  const double side_m = 0.01;
  const QuadraticTetMesh mesh =
      makeQuadraticTetMesh(makeBlockMesh({side_m, side_m, side_m}, {1, 1, 1}));
  FemModel model(mesh, test::liverEnergy(), 1e3 * test::liverEnergy().initialShearModulus());
  model.setSoftening(&test::liverSoftening());
  const auto stretched = [&](double lambda) {
    const Eigen::Vector3d scale(lambda, 1.0 / std::sqrt(lambda), 1.0 / std::sqrt(lambda));
    return Eigen::Matrix3Xd(scale.asDiagonal() * mesh.nodes_m);
  };
  const auto stressAt = [&](double lambda) {
    Eigen::Matrix3Xd gradient;
    EXPECT_TRUE(model.evaluate(stretched(lambda), gradient).isAdmissible);
    double force_N = 0.0;
    for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
      if (mesh.nodes_m(0, i) > side_m - 1e-9) force_N += gradient(0, i);
    }
    return force_N / (side_m * side_m);
  };
  const auto farFaceStress = [&](double lambda) {
    model.softenAt(stretched(lambda));
    return stressAt(lambda);
  };
  const auto virginStress = [&](double lambda) {
    const Eigen::Matrix3d f =
        Eigen::Vector3d(lambda, 1.0 / std::sqrt(lambda), 1.0 / std::sqrt(lambda)).asDiagonal();
    return evaluateIsochoric(test::liverEnergy(), f, false).stress_Pa(0, 0);
  };
  EXPECT_NEAR(farFaceStress(1.3), virginStress(1.3), 1e-9 * virginStress(1.3));
  for (const double lambda : {1.05, 1.2, 1.28}) {
    const double expected = virginStress(lambda) * test::liverSoftening().factor(lambda, 1.3);
    ASSERT_LT(expected, 0.95 * virginStress(lambda)) << lambda;
    EXPECT_NEAR(farFaceStress(lambda), expected, 1e-6 * expected) << lambda;
  }
  EXPECT_NEAR(farFaceStress(1.35), virginStress(1.35), 1e-9 * virginStress(1.35));
  EXPECT_NEAR(farFaceStress(1.3), virginStress(1.3) * test::liverSoftening().factor(1.3, 1.35),
              1e-6 * virginStress(1.3));
  model.clearSoftening();
  EXPECT_NEAR(farFaceStress(1.2), virginStress(1.2), 1e-9 * virginStress(1.2));
  // Between two calls the peak is held: the block unloaded from 1.2 is on the softened curve at
  // once, whatever it was evaluated at before, and past the peak on the virgin one.
  model.softenAt(stretched(1.2));
  const double factor = test::liverSoftening().factor(1.1, 1.2);
  ASSERT_LT(factor, 0.7);
  EXPECT_NEAR(stressAt(1.1), factor * virginStress(1.1), 1e-6 * virginStress(1.1));
  EXPECT_NEAR(stressAt(1.25), virginStress(1.25), 1e-9 * virginStress(1.25));
  EXPECT_NEAR(stressAt(1.1), factor * virginStress(1.1), 1e-6 * virginStress(1.1));
}

/// The block squeezed 25 % along x and jiggled: compressed elements, where the exact Hessian's
/// pressure term and the isochoric tangent's flip modes turn indefinite.
Eigen::Matrix3Xd squeezed(const Eigen::Matrix3Xd& rest) {
  Eigen::Matrix3Xd x = test::stretchedAndJiggled(rest, 5, 3e-4).x;
  x.row(0) *= 0.75 / 1.15;
  x.bottomRows(2) *= 1.12 / 0.94;
  return x;
}

double smallestEigenvalue(const Eigen::SparseMatrix<double>& hessian) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(hessian))
      .eigenvalues()
      .minCoeff();
}

TEST(FemModel, TheDefiniteTangentHasNoNegativeEigenvalueWhereTheExactOneHas) {
  DeformedQuadraticBlock block;
  const Eigen::Matrix3Xd x = squeezed(block.mesh.nodes_m);
  Eigen::Matrix3Xd gradient, definiteGradient;
  Eigen::SparseMatrix<double> exact, definite;
  ASSERT_TRUE(block.model.evaluate(x, gradient, exact, {}).isAdmissible);
  const double scale = Eigen::MatrixXd(exact).cwiseAbs().maxCoeff();
  EXPECT_LT(smallestEigenvalue(exact), -1e-4 * scale);
  block.model.setTangent(FemTangent::Definite);
  const FemState state = block.model.evaluate(x, definiteGradient, definite, {});
  EXPECT_GT(smallestEigenvalue(definite), -1e-12 * scale);
  // The energy and the forces are the exact ones.
  EXPECT_EQ(state.energy_J, block.model.evaluate(x).energy_J);
  EXPECT_EQ((definiteGradient - gradient).cwiseAbs().maxCoeff(), 0.0);
  // At rest the left-out terms vanish and no eigenvalue is negative: the tangents agree.
  Eigen::SparseMatrix<double> atRest;
  block.model.evaluate(block.mesh.nodes_m, gradient, atRest, {});
  block.model.setTangent(FemTangent::Exact);
  block.model.evaluate(block.mesh.nodes_m, gradient, exact, {});
  EXPECT_LT(Eigen::MatrixXd(atRest - exact).cwiseAbs().maxCoeff(), 1e-9 * scale);
}

TEST(FemModel, NewtonOnTheDefiniteTangentSettlesWhereTheExactOneDoes) {
  // The block's low-x face held, its high-x face pushed in 3 mm and held: the same equilibrium
  // from either Hessian, since the energy is the same.
  std::vector<Eigen::Matrix3Xd> settled;
  for (const FemTangent tangent : {FemTangent::Exact, FemTangent::Definite}) {
    DeformedQuadraticBlock block;
    block.model.setTangent(tangent);
    Eigen::Matrix3Xd x = block.mesh.nodes_m;
    std::vector<char> isFixed(static_cast<std::size_t>(x.size()), 0);
    const double low = x.row(0).minCoeff(), high = x.row(0).maxCoeff();
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const double along = block.mesh.nodes_m(0, i);
      x(0, i) -= 0.003 * (along - low) / (high - low);  // the guess: squeezed evenly
      if (along > low + 1e-9 && along < high - 1e-9) continue;
      std::fill_n(isFixed.begin() + 3 * i, 3, char{1});
    }
    FemStaticSolver solver(1e-9, 200);
    const FemSolveReport report = solver.solve(block.model, x, isFixed);
    EXPECT_TRUE(report.converged) << static_cast<int>(tangent);
    settled.push_back(x);
  }
  // The free nodes moved from the even squeeze (the held faces keep the ends from bulging) ...
  const Eigen::Matrix3Xd evenly = [&] {
    Eigen::Matrix3Xd x = DeformedQuadraticBlock().mesh.nodes_m;
    const double low = x.row(0).minCoeff(), high = x.row(0).maxCoeff();
    x.row(0) -= 0.003 * (x.row(0).array() - low).matrix() / (high - low);
    return x;
  }();
  EXPECT_GT((settled[0] - evenly).cwiseAbs().maxCoeff(), 1e-4);
  // ... and to the same place.
  EXPECT_LT((settled[1] - settled[0]).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(FemModel, AKeptAssemblyGivesTheSameHessianAsANewOne) {
  // Evaluated at one place to make the pattern, then at another through it: the same matrix as
  // assembled anew there; and another fixed set makes a pattern of its own.
  DeformedQuadraticBlock block;
  std::vector<char> isFixed(static_cast<std::size_t>(block.x.size()), 0);
  std::fill_n(isFixed.begin(), 9, char{1});
  FemHessianAssembly assembly;
  Eigen::Matrix3Xd gradient;
  Eigen::SparseMatrix<double> kept, fresh;
  block.model.evaluate(block.mesh.nodes_m, gradient, kept, isFixed, &assembly);
  EXPECT_FALSE(assembly.slots.empty());
  const Eigen::Index pattern = kept.nonZeros();
  for (const std::vector<char>& fixed : {isFixed, std::vector<char>(isFixed.size(), 0)}) {
    block.model.evaluate(block.x, gradient, kept, fixed, &assembly);
    block.model.evaluate(block.x, gradient, fresh, fixed);
    ASSERT_EQ(kept.nonZeros(), fresh.nonZeros());
    const double scale = Eigen::MatrixXd(fresh).cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0.0);
    EXPECT_LT(Eigen::MatrixXd(kept - fresh).cwiseAbs().maxCoeff(), 1e-12 * scale);
    EXPECT_EQ(assembly.isFixed, fixed);
  }
  EXPECT_GT(kept.nonZeros(), pattern);  // no fixed DOFs: more entries
}

TEST(FemModel, TwoThreadsEvaluateWhatOneDoes) {
  // A block of enough elements to be cut in two: its energy, gradient and Hessian (made anew and
  // through a kept assembly, with fixed DOFs) on two threads as on one, to round-off, the same
  // bits from call to call; and an inverted element found on either.
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(makeBlockMesh({0.04, 0.02, 0.02}, {8, 4, 4}));
  ASSERT_GE(mesh.tetCount(), FemModel::kElementsForTwoThreads);
  const test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 3, 2e-4);
  std::vector<char> isFixed(static_cast<std::size_t>(mesh.nodes_m.size()), 0);
  std::fill_n(isFixed.begin(), 30, char{1});
  struct Evaluated {
    FemState state;
    Eigen::Matrix3Xd gradient;
    Eigen::MatrixXd hessian;
  };
  const auto evaluated = [&](int threads) {
    FemModel model{mesh, test::liverEnergy(), 50.0 * test::liverEnergy().initialShearModulus()};
    model.setElementThreads(threads);
    FemHessianAssembly assembly;
    Eigen::SparseMatrix<double> hessian;
    Evaluated result;
    model.evaluate(mesh.nodes_m, result.gradient, hessian, isFixed, &assembly);  // the pattern
    result.state = model.evaluate(deformed.x, result.gradient, hessian, isFixed, &assembly);
    result.hessian = Eigen::MatrixXd(hessian);
    Eigen::Matrix3Xd again;
    EXPECT_EQ(model.evaluate(deformed.x, again).energy_J, result.state.energy_J);
    EXPECT_TRUE(again == result.gradient);
    Eigen::Matrix3Xd inverted = deformed.x;
    inverted.col(mesh.tets(0, mesh.tetCount() - 1)) =
        inverted.col(mesh.tets(1, mesh.tetCount() - 1));
    EXPECT_FALSE(model.evaluate(inverted).isAdmissible);
    return result;
  };
  const Evaluated one = evaluated(1), two = evaluated(2);
  ASSERT_TRUE(one.state.isAdmissible);
  ASSERT_TRUE(two.state.isAdmissible);
  EXPECT_NEAR(two.state.energy_J, one.state.energy_J, 1e-12 * std::abs(one.state.energy_J));
  EXPECT_EQ(two.state.minVolumeRatio, one.state.minVolumeRatio);
  EXPECT_EQ(two.state.maxVolumeRatio, one.state.maxVolumeRatio);
  const double forces = one.gradient.cwiseAbs().maxCoeff();
  ASSERT_GT(forces, 0.0);
  EXPECT_LT((two.gradient - one.gradient).cwiseAbs().maxCoeff(), 1e-12 * forces);
  const double stiffness = one.hessian.cwiseAbs().maxCoeff();
  EXPECT_LT((two.hessian - one.hessian).cwiseAbs().maxCoeff(), 1e-12 * stiffness);
  EXPECT_THROW(FemModel(mesh, test::liverEnergy(), 1e5).setElementThreads(3),
               std::invalid_argument);
}

TEST(FemModel, ManyRightHandSidesSolvedOnTwoThreadsAreEachColumnsOwnSolve) {
  // A contact's compliance (a column per candidate DOF) is solved in two halves on two threads:
  // each column as solved alone, and K X = B on the free DOFs (fixed rows zero). The definite
  // tangent, which the solver factorises unshifted.
  DeformedQuadraticBlock block;
  block.model.setTangent(FemTangent::Definite);
  std::vector<char> isFixed(static_cast<std::size_t>(block.x.size()), 0);
  std::fill_n(isFixed.begin(), 9, char{1});
  FemStaticSolver solver;
  FemState state;
  ASSERT_TRUE(solver.factorize(block.model, block.x, isFixed, state));
  const Eigen::Index dofs = block.x.size();
  constexpr Eigen::Index kColumns = 41;  // two threads' halves of unequal size
  Eigen::MatrixXd loads = Eigen::MatrixXd::Zero(dofs, kColumns);
  for (Eigen::Index j = 0; j < kColumns; ++j) loads(dofs - 1 - 2 * j, j) = 1.0 + 0.1 * j;
  Eigen::MatrixXd together = loads;
  solver.solveFactorized(together);
  Eigen::SparseMatrix<double> hessian;
  Eigen::Matrix3Xd gradient;
  block.model.evaluate(block.x, gradient, hessian, isFixed);
  const Eigen::SparseMatrix<double> symmetric = hessian.selfadjointView<Eigen::Lower>();
  const Eigen::MatrixXd dense(symmetric);
  for (Eigen::Index j = 0; j < kColumns; ++j) {
    Eigen::MatrixXd alone = loads.col(j);
    solver.solveFactorized(alone);
    const double scale = alone.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.0) << j;
    EXPECT_LT((together.col(j) - alone).cwiseAbs().maxCoeff(), 1e-12 * scale) << j;
    Eigen::VectorXd residual = dense * together.col(j) - loads.col(j);
    for (Eigen::Index d = 0; d < dofs; ++d) {
      if (isFixed[static_cast<std::size_t>(d)] != 0) {
        EXPECT_EQ(together(d, j), 0.0);
        residual[d] = 0.0;
      }
    }
    EXPECT_LT(residual.cwiseAbs().maxCoeff(), 1e-9 * loads.col(j).cwiseAbs().maxCoeff()) << j;
  }
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
